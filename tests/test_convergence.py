"""The accuracy-versus-time study: cantilever table, Richardson extrapolation, steps."""

import json

import pytest

from helpers import FINAL_DESIGN
from railcheck.cli import main
from railcheck.model.jobs import mesh_sizes
from railcheck.parts import geometry_of
from railcheck.scene import load_scene
from railcheck.studies.convergence import HOLE_RATIO, kinematics_study, richardson, solve_row


@pytest.mark.parametrize("p", [1.0, 2.0, 3.5])
def test_richardson_recovers_a_known_limit_and_order(p):
    f = lambda h: 3.0 + 2.0 * h**p  # noqa: E731
    h = [0.4, 0.25, 0.15]  # non-constant refinement ratio
    f0, order = richardson(h, [f(x) for x in h])
    assert f0 == pytest.approx(3.0, rel=1e-10)
    assert order == pytest.approx(p, rel=1e-8)


def test_richardson_refuses_oscillation():
    with pytest.raises(ValueError):
        richardson([0.4, 0.2, 0.1], [1.0, 1.2, 1.1])


@pytest.mark.slow
def test_cantilever_table_is_monotone_for_p2_and_finest_below_half_percent(capsys):
    assert main(["convergence", "cantilever", "--orders", "1,2", "--sizes", "20,14,10,7", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    p2 = sorted((r for r in rows if r["order"] == 2), key=lambda r: -r["size_m"])
    errors = [abs(r["error_deflection"]) for r in p2]
    assert all(a > b for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 0.005
    assert abs(p2[-1]["error_von_mises"]) < 0.01
    for r in rows:
        assert {
            "order",
            "size_m",
            "dofs",
            "seconds",
            "peak_memory_bytes",
            "tip_deflection_m",
            "max_von_mises_Pa",
            "error_deflection",
            "error_von_mises",
        } <= set(r)
        assert set(r["seconds"]) == {"mesh", "assembly", "solve", "stress"}
        assert r["peak_memory_bytes"] > 0
    # P1 locks: every P1 row is far worse than the coarsest P2 row
    p1 = [abs(r["error_deflection"]) for r in rows if r["order"] == 1]
    assert min(p1) > 10 * errors[0]


def test_kinematics_steps_study_reaches_four_figures():
    rows, ref = kinematics_study([100, 1000, 5000], reference_steps=50_000)
    by = {r["steps"]: r for r in rows}
    assert by[5000]["four_significant_figures"]
    assert by[100]["max_abs_error"] > by[1000]["max_abs_error"] > by[5000]["max_abs_error"]


def test_unknown_target_exits_2(capsys):
    assert main(["convergence", "flux-capacitor"]) == 2
    assert "TARGET" in capsys.readouterr().err


#: converged references of the curved-P2 study (docs/performance.md "What accuracy costs") for
#: the plates: Richardson extrapolations of the three finest meshes of `railcheck convergence
#: PART --orders 2 --sizes 12,8.5,6,4.2` (PF_4b_006), `12,8.5,6,4.2,3` (PF_4b_003_v2), the
#: 2013 load case (clamped at the seat / base). (tip deflection m, peak von Mises Pa)
#: PF_4b_006 rerun when the rails became the grooved profile (the dynamics carry 3.16 kg/m:
#: reactions 9% larger), for the v2 joints' loads (each rail's pivot midway between its first
#: two holes: 7.1170154e-7 m, 2.9103827 MPa) and for the v2 upper plate (the shaft's 25 mm bore
#: midway between its two screws, 120 x 75 x 15 mm: observed orders 1.41 and 2.37, the default
#: 6 mm mesh -0.17% / -2.2%, 2026-12-02); PF_4b_003_v2's explicit loads do not depend on them.
CONVERGED = {
    "PF_4b_006": (8.3117480e-8, 2.0011148e6),
    "PF_4b_003_v2": (1.0538050e-4, 92.856826e6),
}


@pytest.mark.slow
@pytest.mark.parametrize("part", list(CONVERGED))
def test_default_mesh_is_within_the_accuracy_targets_of_the_converged_study(part):
    """Each plate on the default scene's mesh (curved P2, size from the registry, holes at
    0.3 x size): tip deflection within 1% and peak von Mises within 5% of the study's
    converged values, the targets the defaults were chosen for."""

    size, hole = mesh_sizes(load_scene(None).mesh, geometry_of(part, {}).kind)
    assert hole == pytest.approx(HOLE_RATIO * size)
    row = solve_row(part, "P2", size)
    tip, peak = CONVERGED[part]
    assert abs(row["tip_deflection_m"] / tip - 1) < 0.01, row["tip_deflection_m"] / tip - 1
    assert abs(row["max_von_mises_Pa"] / peak - 1) < 0.05, row["max_von_mises_Pa"] / peak - 1


#: the rails' references, on the verdict's model: the default scene's three rails as free
#: bodies with the table-top rig's weight out of plane, 720 steps, `[mesh] size = "5 mm"`,
#: `hole_size = "1.5 mm"` (622k DOFs on the crank rail; the finest mesh is the reference: the
#: peaks sit at hole edges and rise slowly, 2-3% from the 7 mm meshes, with no steady order;
#: docs/performance.md "The free-body rails"). (cycle peak von Mises Pa, minimum fatigue factor,
#: deflection m)
FREE_RAILS_CONVERGED = {
    # the v2 joints, `python benchmarks/free_body_rails.py --meshes 20:6,20:4,20:3,10:4,5:1.5`,
    # 2026-12-02, at the default scene's fatigue reliability 0.99
    "crank-rail": (199.38919e6, 1.5221442, 4.6400577e-3),
    "coupler-rail": (19.352005e6, 18.550839, 0.24083197e-3),
    "rocker-rail": (128.74721e6, 5.4148837, 0.74478781e-3),
}

FREE_RAILS_SCENE = (
    FINAL_DESIGN
    + """speed = "1 Hz"
steps = 720
[check]
parts = ["crank-rail", "coupler-rail", "rocker-rail"]
support = "free-body"
"""
)


@pytest.fixture(scope="module")
def free_rails():
    import tomllib

    from railcheck.check.pipeline import run_pipeline
    from railcheck.scene import parse_scene

    return run_pipeline(parse_scene(tomllib.loads(FREE_RAILS_SCENE), "free rails"), jobs=1)


@pytest.mark.slow
@pytest.mark.parametrize("part", list(FREE_RAILS_CONVERGED))
def test_the_default_rail_mesh_against_the_converged_free_bodies(free_rails, part):
    """The rails on their default mesh (10 mm, 4 mm at the holes and the grooves) as the
    verdict loads them, against the references above, at the targets: 5% on the peak and
    the fatigue factor, 1% on the deflection. Measured: the crank rail, which governs the
    rig, -4.4% / +2.0% / -0.24%, the coupler -2.6% / +3.7% / -0.55%, the rocker -3.5% /
    +3.7% / -0.69%. The old default (20 mm, 6 mm at the holes) missed them: -8.9% / +3.1%,
    -8.5% / +10.0%, -7.8% / +15.3%; so do 20 mm with 4 or 3 mm holes on the rocker (-5.9%,
    -9.2%): the peaks scatter by a few per cent from one hole mesh to the next
    (docs/performance.md)."""
    result = free_rails.parts[part]
    peak, fatigue, deflection = FREE_RAILS_CONVERGED[part]
    stress_tol, deflection_tol = 0.05, 0.01
    assert abs(result.verdict_stress / peak - 1) < stress_tol, result.verdict_stress / peak - 1
    assert abs(result.cycle.fatigue.min_safety_factor / fatigue - 1) < stress_tol
    assert abs(result.cycle.envelope.max_tip / deflection - 1) < deflection_tol, (
        result.cycle.envelope.max_tip / deflection - 1
    )
