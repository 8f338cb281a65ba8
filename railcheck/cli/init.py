"""``railcheck init [FILE]``: write a commented starter scene."""

from __future__ import annotations

import tomllib
from importlib import resources

from railcheck.base.errors import EXIT_PASS, InputError
from railcheck.files import atomic_write_text, writable_file
from railcheck.scene import parse_scene

HELP = "write a commented starter scene"


def add_args(p) -> None:
    p.add_argument("file", nargs="?", default="scene.toml", help="where to write it (default scene.toml)")
    p.add_argument("--force", action="store_true", help="replace an existing file")


def run(args) -> int:
    path = writable_file(args.file, "FILE")
    if path.exists() and not args.force:
        raise InputError("FILE", f"{path} exists (use --force to replace it)")
    text = resources.files("railcheck").joinpath("scenes", "starter.toml").read_text(encoding="utf-8")
    parse_scene(tomllib.loads(text), "starter.toml")  # the starter is always a valid scene
    atomic_write_text(path, text)
    print(f"wrote {path}: edit it, then run: railcheck check {path}")
    return EXIT_PASS
