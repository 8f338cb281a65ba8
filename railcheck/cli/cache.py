"""``railcheck cache [--clear]``: what the on-disk caches hold (the mesh cache and the
unit-field store, :mod:`railcheck.fea.store`), and clearing them."""

from __future__ import annotations

from typing import Any

from railcheck import environment
from railcheck.base.errors import EXIT_PASS
from railcheck.fea.store import UnitStore, clear_store, file_size, store_info
from railcheck.files import to_json

HELP = "show or clear the mesh cache and the unit-field store"


def add_args(p) -> None:
    p.add_argument("--clear", action="store_true", help="remove every mesh and unit-field entry")
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")


def _mesh_entries():
    root = environment.cache_dir()
    return root, ([p for p in root.glob("*.npz") if not p.name.startswith(".") and p.is_file()] if root.is_dir() else [])


def _store() -> UnitStore:
    """The unit-field store the environment names (shown and cleared even when
    ``RAILCHECK_STORE=0`` bypasses it)."""
    return UnitStore(environment.cache_dir() / "unit-fields", environment.store_cap_bytes())


def run(args) -> int:
    root, meshes = _mesh_entries()
    if args.clear:
        removed_meshes = 0
        for p in meshes:
            try:
                p.unlink()
                removed_meshes += 1
            except OSError:
                pass
        removed_fields = clear_store(_store())
        print(f"removed {removed_meshes} mesh entries and {removed_fields} unit-field entries from {root}")
        return EXIT_PASS
    info = store_info(_store())
    out = {
        "mesh_cache": {"directory": str(root), "entries": len(meshes), "bytes": sum(file_size(p) for p in meshes)},
        "unit_field_store": {
            "directory": str(info.directory),
            "entries": info.entries,
            "bytes": info.bytes,
            "cap_bytes": info.cap,
        },
    }
    if args.json:
        print(to_json(out))
        return EXIT_PASS
    m: dict[str, Any] = out["mesh_cache"]
    u: dict[str, Any] = out["unit_field_store"]
    print(f"mesh cache:       {m['entries']} entries, {m['bytes'] / 1e6:.1f} MB in {m['directory']}")
    print(
        f"unit-field store: {u['entries']} entries, {u['bytes'] / 1e6:.1f} MB of {u['cap_bytes'] / 1e6:.0f} MB "
        f"(RAILCHECK_STORE_MB) in {u['directory']}"
    )
    print("railcheck cache --clear removes both; RAILCHECK_CACHE moves them; RAILCHECK_STORE=0 bypasses the store")
    return EXIT_PASS
