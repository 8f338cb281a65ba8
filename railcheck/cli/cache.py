"""``railcheck cache [--clear]``: what the on-disk caches hold (the mesh cache and the
unit-field store, :mod:`railcheck.fea.store`), and clearing them."""

from __future__ import annotations

from typing import Any

from railcheck import environment
from railcheck.base.entries import clear_entries, is_own_entry
from railcheck.base.errors import EXIT_PASS
from railcheck.fea.store import UnitStore, clear_store, file_size, store_info
from railcheck.files import to_json
from railcheck.geometry.cache import ENTRY_NAME

HELP = "show or clear the mesh cache and the unit-field store"


def add_args(p) -> None:
    p.add_argument(
        "--clear", action="store_true", help="remove every mesh and unit-field entry railcheck wrote (nothing else)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")


def _mesh_entries():
    root = environment.cache_dir()
    return root, ([p for p in root.glob("*.npz") if is_own_entry(p, ENTRY_NAME)] if root.is_dir() else [])


def _store() -> UnitStore:
    """The unit-field store the environment names (shown and cleared even when
    ``RAILCHECK_STORE=0`` bypasses it)."""
    return UnitStore(environment.cache_dir() / "unit-fields", environment.store_cap_bytes())


def run(args) -> int:
    root, meshes = _mesh_entries()
    if args.clear:
        return _clear(root)
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


def _clear(root) -> int:
    """Remove what railcheck wrote in both caches and name what it left."""
    store = _store()
    removed_meshes, left = clear_entries(root, ENTRY_NAME, known=frozenset({store.directory.name}))
    removed_fields, left_fields = clear_store(store)
    left += [f"{store.directory.name}/{n}" if not n.endswith("(a link: not followed)") else n for n in left_fields]
    print(f"removed {removed_meshes} mesh entries and {removed_fields} unit-field entries from {root}")
    if left:
        shown = ", ".join(left[:8]) + (f" and {len(left) - 8} more" if len(left) > 8 else "")
        print(f"left {len(left)} files railcheck did not write: {shown}")
    return EXIT_PASS
