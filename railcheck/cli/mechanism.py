"""``railcheck mechanism NAME``: seed 002's study of a planar mechanism in body coordinates:
a planar scene (``[mechanism] kind = "planar"``), a catalogue entry, or a rig scene's own
linkage. Prints mobility, motion, tracers and reactions; writes summary.json, tracers.csv,
reactions.csv and the interactive mechanism.html into the results folder."""

from __future__ import annotations

import re
from pathlib import Path

from railcheck.base.errors import EXIT_PASS
from railcheck.files import atomic_write_text, to_json, writable_dir, writable_file
from railcheck.kinematics.planar.catalogue import CATALOGUE
from railcheck.studies.mechanism import mechanism_scene, write_gif
from railcheck.studies.planar_outputs import planar_lines, planar_summary, tracers_csv, write_planar_outputs
from railcheck.studies.planar_page import write_planar_page
from railcheck.studies.planar_study import study_planar
from railcheck.studies.planar_symbolic import equations_text

HELP = "any planar mechanism in body coordinates: mobility, motion, tracers, reactions, an interactive page"
PARSER = {
    "description": 'The study of a planar mechanism in body coordinates: a planar scene file ([mechanism] kind = "planar"), '
    "a catalogue mechanism of the mechanisms study, or a rig scene's own four-bar or slider-crank.",
    "epilog": "exit status: 0 studied (a motion that stops at a lock-up or a dead centre says so), 2 bad input "
    "(one line naming the field).",
}


def add_args(p) -> None:
    p.add_argument("name", help=f"a scene .toml, or a catalogue name ({', '.join(CATALOGUE)})")
    p.add_argument("--steps", type=int, help="driver steps over its range (default: the scene's, else 361)")
    p.add_argument("--out", metavar="DIR", help="results folder (default: results/mechanism-NAME)")
    p.add_argument("--json", action="store_true", help="print summary.json to stdout")
    p.add_argument("--equations", action="store_true", help="print the constraint equations symbolically (sympy)")
    p.add_argument("--csv", metavar="FILE", help="also write the tracers' table (tracers.csv's columns) to FILE")
    p.add_argument("--html", metavar="FILE", help="also write the interactive page to FILE")
    p.add_argument("--gif", metavar="FILE", help="an animation of the mechanism")


def default_out(name: str) -> Path:
    """results/mechanism-<the scene file's stem or the catalogue name>."""
    stem = Path(name).stem if name.endswith(".toml") else name
    return Path("results") / ("mechanism-" + (re.sub(r"[^A-Za-z0-9_.-]+", "-", stem) or "scene"))


def run(args) -> int:
    extra = {
        k: writable_file(v, f"--{k}", ".gif" if k == "gif" else None)
        for k in ("csv", "html", "gif")
        if (v := getattr(args, k))
    }
    out = writable_dir(args.out or default_out(args.name), "--out")
    study = study_planar(mechanism_scene(args.name, args.steps))
    summary = planar_summary(study)
    written = write_planar_outputs(study, summary, out)
    if "csv" in extra:
        atomic_write_text(extra["csv"], tracers_csv(study))
    if "html" in extra:
        write_planar_page(extra["html"], study)
    if "gif" in extra:
        write_gif(extra["gif"], study.mechanism, study.motion, next(iter(study.tracers.values()))[:, :2])
    if args.json:
        print(to_json(summary))
        return EXIT_PASS
    print("\n".join(planar_lines(summary)))
    if args.equations:
        print(equations_text(study.mechanism))
    for path in written + list(extra.values()):
        print(f"wrote {path}")
    return EXIT_PASS
