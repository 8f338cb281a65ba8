"""Pictures an engineer reads at a glance: caption text at least 2.5% of the picture's
height and inside it (measured on the rendered text), colour-bar labels that read distinct
values, and cycle plots scaled to their data with the limit drawn only when in range."""

import numpy as np
import pytest

from railcheck.report.plots import cycle_axis_top
from railcheck.report.render import caption_box, caption_font_size, colour_bar_format, fit_caption, offscreen_pyvista

LONG = (
    "PF_4b_006: cycle peak 2.9 MPa at crank 13.5 deg\nlimit 375 MPa, FoS 131; largest tip deflection 0.000878 mm\n"
    "shape x 9.71e+03 (largest displacement 5% of the part); black: the clamp; magenta: its singular zone; red: joint force"
)


@pytest.mark.parametrize("size", [(1600, 500), (1200, 1000)])
def test_caption_is_large_enough_and_inside_the_picture(size):
    pv = offscreen_pyvista()
    plotter = pv.Plotter(off_screen=True, window_size=size)
    plotter.add_mesh(pv.Cube())
    font = caption_font_size(size[1])
    lines = fit_caption(plotter, LONG, size, font)
    actor = plotter.actors["caption"]
    x0, x1, y0, y1 = caption_box(plotter, actor)
    plotter.close()
    assert lines >= 3
    assert (y1 - y0) / lines >= 0.025 * size[1]  # each line at least 2.5% of the height
    assert 0 <= x0 and x1 <= size[0] and 0 <= y0 and y1 <= size[1]  # nothing clipped


@pytest.mark.parametrize("top", [0.05, 0.3, 2.9, 9.9, 24.0, 91.3, 400.0])
def test_colour_bar_labels_read_distinct_values(top):
    fmt = colour_bar_format(top)
    labels = [fmt % (top * i / 5) for i in range(6)]
    assert len(set(labels)) == 6, labels
    assert float(labels[-1]) == pytest.approx(top, rel=0.2)


def test_cycle_plot_axis_follows_the_data_and_shows_the_limit_only_in_range():
    assert cycle_axis_top(2.9e6, 2.8e6, 375e6) == pytest.approx(1.15 * 2.9e6)  # a 2.9 MPa cycle on its own scale
    assert cycle_axis_top(300e6, 250e6, 375e6) == pytest.approx(1.05 * 375e6)  # the limit in range: drawn
    top = cycle_axis_top(100e6, 120e6, 375e6)
    assert top >= 1.15 * 120e6 and np.isclose(top, 1.15 * 120e6)  # the seed method's peak is on the axis too


def test_help_is_plain_text_without_jargon():
    """`--help` of every command reads as plain text: no reStructuredText backticks and no
    "seed" (the code's name for the 2013 study, undefined for a reader of the help)."""
    import argparse

    from railcheck.cli import build_parser

    parser = build_parser()
    texts = [parser.format_help()]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            texts += [sub.format_help() for sub in action.choices.values()]
    assert len(texts) >= 8
    for text in texts:
        assert "`" not in text and "seed" not in text.lower(), text


def _fake_part(weight):
    from types import SimpleNamespace

    import numpy as np

    loads = SimpleNamespace(is_free_plate=False, is_on_foundation=False, weight=weight, factor=1.4, explicit=None)
    job = SimpleNamespace(free_body=object(), loads=loads)
    cycle = SimpleNamespace(
        history=SimpleNamespace(crank_angle_deg=12.0),
        C=np.zeros((2, 1)),
        envelope=SimpleNamespace(max_tip=1e-4),
        fatigue=SimpleNamespace(min_safety_factor=0.8, required=1.0),
    )
    return SimpleNamespace(
        cycle=cycle,
        job=job,
        verdict_stress=1.2e8,
        limit=3.75e8,
        passed=False,
        utilisation=1.25,
        governing_criterion="fatigue",
    )


def test_caption_says_when_the_part_carries_its_weight_out_of_plane():
    from railcheck.report.render import picture_caption

    assert "weight out of plane" in picture_caption("crank-rail", _fake_part(weight=object()), 30.0)
    assert "weight" not in picture_caption("crank-rail", _fake_part(weight=None), 30.0)


def test_caption_gives_the_verdict_what_governs_and_that_the_forces_are_factored():
    from railcheck.report.render import picture_caption

    text = picture_caption("crank-rail", _fake_part(weight=None), 30.0)
    assert text.startswith("crank-rail: FAIL, utilisation 125% (fatigue n 0.80 against 1)")
    assert "x1.4 (factored)" in text


@pytest.mark.parametrize(
    ("size", "largest", "scale"),
    [(0.7, 4.34e-3, 5.0), (0.1, 1.04e-6, 1000.0), (0.1, 1e-3, 5.0), (0.1, 2.5e-3, 2.0), (1.0, 0.05, 1.0), (0.1, 0.0, 0.0)],
)
def test_one_deformation_scale_rule_for_every_part(size, largest, scale):
    from railcheck.report.render import deformation_scale

    assert deformation_scale(size, largest) == scale
    if largest > 0:  # never drawn beyond 5% of the part, never blown up past x1000
        assert scale * largest <= 0.05 * size * (1 + 1e-12) and scale <= 1000.0


def test_the_utilisation_picture_draws_the_verdicts_field_on_one_scale(tmp_path):
    """Each vertex's utilisation is the verdict's own (its envelope over the limit, the
    required fatigue factor over its own): never above the part's, which also reads the
    mid-edge nodes, and within a few percent of it on the default bracket; the picture is
    written, and a part checked without node fields gets none (no picture of nothing)."""
    import dataclasses

    from railcheck.check.pipeline import run_pipeline
    from railcheck.report.utilisation_picture import node_utilisation, render_utilisation
    from railcheck.scene import parse_scene

    data = {
        "check": {"parts": ["PF_4b_003_v2"]},
        "loads": {"PF_4b_003_v2": {"longitudinal": "250 N", "transverse": "250 N"}},
        "output": {"vtk": False, "png": True, "plots": False},
    }
    part = run_pipeline(parse_scene(data, "test")).parts["PF_4b_003_v2"]
    u = node_utilisation(part)
    assert u.shape == (part.mesh.points.shape[0],)
    assert 0.8 * part.utilisation <= u.max() <= part.utilisation * (1 + 1e-9)
    stress = part.cycle.envelope.node_envelope
    if stress is not None:
        assert np.all(u >= stress[: u.size] / part.limit * (1 - 1e-12))
    path = render_utilisation(tmp_path / "u.png", "PF_4b_003_v2", part)
    assert path.read_bytes()[:4] == b"\x89PNG"
    bare = dataclasses.replace(
        part, cycle=dataclasses.replace(part.cycle, fatigue=dataclasses.replace(part.cycle.fatigue, node_factor=None))
    )
    assert render_utilisation(tmp_path / "none.png", "PF_4b_003_v2", bare) is None


@pytest.fixture(scope="module")
def checked_parts():
    """The built-in setting's crank and rocker rails (coarse: linear elements, no grooves)
    and its joint plate, checked with the table-top rig's weight."""
    from helpers import COARSE_RAILS, FINAL_DESIGN
    from railcheck.api import scene_of
    from railcheck.check.pipeline import run_pipeline

    text = (
        FINAL_DESIGN
        + '[check]\nparts = ["crank-rail", "rocker-rail", "PF_4b_006"]\n'
        + COARSE_RAILS.replace('"7 mm"', '"6 mm"')
    )
    return run_pipeline(scene_of(text)).parts


@pytest.mark.slow  # three parts checked and drawn: about 15 s
@pytest.mark.parametrize("name", ["crank-rail", "rocker-rail", "PF_4b_006"])
def test_force_labels_sit_off_the_part_clear_of_holes_labels_and_caption(checked_parts, tmp_path, name):
    from railcheck.report.labels import Box, conflicts_among
    from railcheck.report.render import render_part

    pic = render_part(tmp_path / f"{name}.png", name, checked_parts[name])
    picture = Box(0.0, 0.0, *pic.size)
    assert pic.labels and pic.holes.shape[0] >= 2  # forces labelled, holes found
    assert conflicts_among(list(pic.labels), pic.holes, picture) == []  # no overlap, no hole covered, inside
    assert not any(b.overlaps(pic.part) or b.overlaps(pic.caption) for b in pic.labels)  # off the part, under the title
    assert pic.caption.y0 >= pic.part.y1  # the title above the part
    assert pic.part.x1 - pic.part.x0 >= 0.7 * pic.size[0]  # the part fills the width (it filled 45%)
    assert pic.caption.y1 - pic.caption.y0 < 3 * 1.7 * 18  # a two-line title


@pytest.mark.slow  # the same fixture
def test_the_rocker_governed_out_of_plane_is_drawn_from_the_side_with_its_weight(checked_parts):
    from railcheck.report.render import governing_view, picture_caption

    rocker, crank = checked_parts["rocker-rail"], checked_parts["crank-rail"]
    assert governing_view("rocker-rail", rocker.solution.displacement) == "xz"  # it sags more than it bends in plane
    assert governing_view("crank-rail", crank.solution.displacement) == "xy"
    assert picture_caption("rocker-rail", rocker, 50.0).count("\n") == 1  # a two-line title


@pytest.mark.slow  # the same fixture
def test_every_part_picture_shares_one_von_mises_scale_unless_asked_per_part(checked_parts):
    from railcheck.report.render import stress_scale_top

    tops = {stress_scale_top(p) for p in checked_parts.values()}
    assert tops == {400.0}  # 0 to 400 MPa for the 375 MPa limit, every part
    for p in checked_parts.values():
        own = stress_scale_top(p, "part")
        assert p.verdict_stress / 1e6 <= own < 2.0 * p.verdict_stress / 1e6  # a round value at or above its peak
