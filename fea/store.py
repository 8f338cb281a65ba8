"""The unit-field store: a part's solved unit cases (:func:`railcheck.fea.unitcases.solve_unit_cases`)
kept on disk, so a part whose mesh, material, supports and cases are unchanged is not
assembled or solved again: a new setting only changes the coefficients of fields already
solved.

An entry is keyed by a SHA-256 of everything the fields depend on: the mesh's arrays
(points, elements, groups, curved edges), the material, the supports, every unit case
(its dataclass representation: holes, direction, shares, pivots), the element order, the
tip group, the support's exclusion distance, the free-body and mode requests, and the
versions of this store's format, railcheck and scikit-fem. The entry (an uncompressed
``.npz``) also stores that payload and the names of its arrays, both checked on every
read, and the zip format's CRC-32 of every member (its array's bytes and header), checked
as it is read (:func:`read_members`: each member read whole into its array, then its
CRC-32 over all of it): a swapped, truncated or bit-flipped entry is reported and solved
again (and rewritten). A second hash of the arrays would cost a warm check 0.15 s and catch nothing
more (a random change escapes a CRC-32 once in 4e9). Writes go to a
per-process temporary name and are renamed into place, so two runs filling the same entry
both read whole files (the last rename wins; both wrote the same fields). A read touches
the entry; after a write the least recently used entries beyond the size cap are removed.

A store is a folder and a size cap (:class:`UnitStore`), given by the caller: the
application's is ``$RAILCHECK_CACHE/unit-fields`` capped at ``$RAILCHECK_STORE_MB`` MB
(:mod:`railcheck.environment`). ``railcheck cache`` shows and clears it.
Units: the fields' own (Pa, m, N).
"""

from __future__ import annotations

import functools
import hashlib
import hmac
import json
import os
import re
import stat
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from railcheck.base.code import code_hash
from railcheck.base.entries import clear_entries, is_own_entry
from railcheck.base.temporaries import remove_dead_temporaries, temporary_name
from railcheck.geometry.meshdata import MeshData

from .dynamic import DynamicModel
from .materials import Material
from .superpose import UnitFields
from .unitcases import UnitSolve, solve_unit_cases

__all__ = [
    "StoreInfo",
    "UnitRequest",
    "UnitStore",
    "clear_store",
    "is_stored",
    "reads_shared",
    "solve_stored",
    "store_info",
]


def code_of_entries() -> str:
    """The hash of the code that solves and stores unit fields (the FE package,
    :func:`railcheck.base.code.code_hash`): part of every entry's key, so an entry written
    by other code (an older format, another solver) is never read."""
    return code_hash("railcheck.fea")


#: an entry's file name: the first 40 hex digits of its payload's SHA-256
ENTRY_NAME = re.compile(r"(?P<key>[0-9a-f]{40})\.npz")


@dataclass(frozen=True)
class UnitStore:
    """Where solved unit fields are kept: ``directory`` (created on first write) and
    ``cap`` bytes, beyond which the least recently used entries are removed."""

    directory: Path
    cap: int


@functools.lru_cache(maxsize=1)
def _versions() -> str:
    from importlib.metadata import PackageNotFoundError, version

    out = []
    for package in ("railcheck", "scikit-fem"):
        try:
            out.append(f"{package}={version(package)}")
        except PackageNotFoundError:
            out.append(f"{package}=?")
    return ",".join(out)


@dataclass(frozen=True, eq=False)
class UnitRequest:
    """Everything a part's unit solve depends on (the arguments of
    :func:`railcheck.fea.unitcases.solve_unit_cases` but the solver and the progress)."""

    points: np.ndarray
    tets: np.ndarray
    groups: dict
    material: Material
    supports: list
    cases: dict
    order: int = 2
    tip_group: str | None = None
    exclude: float = 0.0
    curved: tuple | None = None
    free_body: object = None
    modes: object = None

    def payload(self) -> str:
        """The text every input is reduced to (arrays by their SHA-256)."""
        h = hashlib.sha256()
        for a in (self.points, self.tets, *(self.curved or ())):
            h.update(np.ascontiguousarray(a).tobytes())
        for name in sorted(self.groups):
            h.update(name.encode())
            h.update(np.ascontiguousarray(self.groups[name]).tobytes())
        return repr(
            (
                code_of_entries(),
                _versions(),
                h.hexdigest(),
                repr(self.material),
                tuple(self.supports),
                tuple((name, repr(case)) for name, case in self.cases.items()),
                int(self.order),
                self.tip_group,
                float(self.exclude),
                self.curved is not None,
                repr(self.free_body),
                repr(self.modes),
            )
        )

    def path(self, store: UnitStore, payload: str | None = None) -> Path:
        """The entry's file in ``store``."""
        return store.directory / f"{_key(payload or self.payload())}.npz"


def _key(payload: str) -> str:
    return hashlib.sha256(payload.encode()).hexdigest()[:40]


def _arrays(fields, solve) -> dict[str, np.ndarray]:
    """Everything an entry gives back, as named arrays."""
    out = {
        "stress": fields.stress,
        "tip": fields.tip,
        "displacement": fields.displacement,
        "nodes": fields.nodes,
        "verdict_mask": fields.verdict_mask,
        "names": np.array(fields.names, dtype=str),
        "resultants": solve.resultants,
        "support_reactions": solve.support_reactions,
    }
    for name in ("cells", "support", "loaded"):
        value = getattr(fields, name)
        if value is not None:
            out[name] = value
    if solve.imbalance is not None:
        out["imbalance"] = solve.imbalance
    if solve.modes is not None:
        out["modes_hz"], out["modes_loads"] = solve.modes.hz, solve.modes.modal_loads
    for i, (key, tip) in enumerate((fields.tips or {}).items()):
        out[f"tip{i}_key"], out[f"tip{i}"] = np.array(repr(key)), tip
    for i, (key, found) in enumerate((solve.mode_sets or {}).items()):
        out[f"set{i}_key"] = np.array(repr(key))
        out[f"set{i}_hz"], out[f"set{i}_loads"] = found.hz, found.modal_loads
    return out


def _meta(solve, arrays: dict[str, np.ndarray]) -> str:
    return json.dumps(
        {
            "arrays": sorted(arrays),
            "dofs": solve.dofs,
            "elements": solve.elements,
            "vertices": solve.vertices,
            "solver": solve.solver,
            "mode_sets": solve.mode_sets is not None,
        },
        sort_keys=True,
        default=str,
    )


def write_entry(path: Path, payload: str, fields, solve, cap: int) -> str | None:
    """Write an entry atomically (per-process temporary name, then a rename). None when
    written, else why not (the system's words: a full disk, a read-only store, a file
    where its folder should be): a store that cannot be written only costs time, and its
    caller says so (:func:`solved_origin`)."""
    arrays = _arrays(fields, solve)
    meta = _meta(solve, arrays)
    tmp = temporary_name(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_dead_temporaries(path.parent)
        np.savez(tmp, payload=np.array(payload), meta=np.array(meta), **arrays)  # type: ignore[arg-type]  # numpy stubs type **kwds as allow_pickle
        _add_seal(tmp, store_key(path.parent))
        os.replace(tmp, path)
    except OSError as exc:
        try:  # nothing half-written is left (and no folder may exist to hold any)
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        return exc.strerror or type(exc).__name__
    evict(path.parent, cap, keep=path)
    return None


def solved_origin(damaged: str | None, unstored: str | None) -> str:
    """What :func:`solve_stored` says of fields it solved: "solved", or why a stored entry
    was solved again (``damaged``), and why the new entry is not stored (``unstored``:
    the next run solves them again: a full disk costs every later run the solve, unsaid
    before, 18 s more on the whole rig's builds)."""
    said = [f"stored unit fields {damaged}: solved again"] if damaged else []
    if unstored:
        said.append(f"unit fields not stored ({unstored}): the next run solves them again")
    return "; ".join(said) or "solved"


def read_entry(path: Path, payload: str):
    """((UnitFields, UnitSolve), None) for a sound entry made for ``payload``; (None, why)
    for a damaged, swapped or stale one; (None, None) when there is none."""
    if not path.exists():
        return None, None
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return None, "not a regular file"
        crcs: dict[str, tuple[int, int]] = {}
        arrays = read_members(path, crcs)  # each member's CRC-32 checked over its bytes
        stored_payload, meta = str(arrays.pop("payload")), str(arrays.pop("meta"))
        if stored_payload != payload:
            return None, "made for other inputs"
        if not _sealed(str(arrays.pop(SEAL, "")), crcs, store_key(path.parent, create=False)):
            return None, "not what this store wrote (its seal does not match its contents)"
        fields, solve = _entry(arrays, json.loads(meta))
    except Exception as exc:  # noqa: BLE001 - any unreadable or incomplete file is a damaged entry
        return None, f"unreadable ({type(exc).__name__})"
    try:
        os.utime(path)  # recently used: evicted last
    except OSError:
        pass
    return (fields, solve), None


#: the member that seals an entry (:func:`seal_of`)
SEAL = "seal"
KEY_FILE = ".key"


def store_key(directory: Path, create: bool = True) -> bytes:
    """The store's secret (32 random bytes in ``directory/.key``, made on its first
    write; b"" when there is none and ``create`` is false, or it cannot be read)."""
    path = directory / KEY_FILE
    try:
        key = path.read_bytes()
        if len(key) == 32 or not create:
            return key if len(key) == 32 else b""
    except OSError:
        if not create:
            return b""
    import secrets

    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:  # another run made it first: wait for its 32 bytes
        for _ in range(100):
            key = path.read_bytes()
            if len(key) == 32:
                return key
            time.sleep(0.01)
        raise OSError(f"{path}: not a store key") from None
    with os.fdopen(fd, "wb") as f:
        f.write(secrets.token_bytes(32))
    return path.read_bytes()


def directory_record(info) -> tuple:
    """What the zip's directory says of a member (``zipfile.ZipInfo``): CRC-32, size,
    offset and the fields no reader checks (times, attributes, versions, flags)."""
    return (
        info.CRC,
        info.file_size,
        info.header_offset,
        info.date_time,
        info.external_attr,
        info.internal_attr,
        info.create_version,
        info.extract_version,
        info.flag_bits,
        info.create_system,
        info.volume,
    )


def seal_of(key: bytes, crcs: dict) -> str:
    """HMAC-SHA256 under the store's ``key`` of every member's name and directory record
    (``crcs``: name -> :func:`directory_record`, the seal's own member left out). Each member's CRC is
    checked against its bytes on read, so the seal ties the entry's contents to the
    store that wrote it: an entry rewritten (``np.savez`` makes fresh CRCs), scaled or
    copied from another store does not match it."""
    h = hmac.new(key, digestmod="sha256")
    for name in sorted(n for n in crcs if n != f"{SEAL}.npy"):
        h.update(f"{name}:{crcs[name]!r};".encode())
    return h.hexdigest()


def _add_seal(path: Path, key: bytes) -> None:
    """Append the seal member to the freshly written entry ``path``."""
    import io
    import zipfile

    from numpy.lib import format as npy

    with zipfile.ZipFile(path, "a") as z:
        crcs = {i.filename: directory_record(i) for i in z.infolist()}
        buffer = io.BytesIO()
        npy.write_array(buffer, np.array(seal_of(key, crcs)))
        z.writestr(zipfile.ZipInfo(f"{SEAL}.npy"), buffer.getvalue())


def _sealed(seal: str, crcs: dict, key: bytes) -> bool:
    return bool(key) and hmac.compare_digest(seal, seal_of(key, crcs))


def read_members(path: Path, crcs: dict | None = None) -> dict[str, np.ndarray]:
    """Name -> array of every member of an uncompressed ``.npz`` (``np.savez``'s), each
    read whole into its array and its CRC-32 checked over all its bytes (``np.load``
    reads a member through the zip module 256 KB at a time: 0.5 GB/s here, a rail's
    166 MB basis 0.3 s). ValueError for a compressed, object or malformed member, a short
    read or a CRC that differs. ``crcs``, when given, receives each member's file name ->
    (CRC-32, size), as checked."""
    import zipfile

    from numpy.lib import format as npy

    out = {}
    with open(path, "rb") as f, zipfile.ZipFile(f) as z:
        for info in z.infolist():
            if info.compress_type != zipfile.ZIP_STORED or not info.filename.endswith(".npy"):
                raise ValueError(f"{info.filename}: not a stored .npy member")
            f.seek(info.header_offset)
            local = f.read(30)
            if len(local) != 30 or local[:4] != b"PK\x03\x04":
                raise ValueError(f"{info.filename}: no local header")
            start = info.header_offset + 30 + int.from_bytes(local[26:28], "little") + int.from_bytes(local[28:30], "little")
            f.seek(start)
            out[info.filename[:-4]] = _member_array(f, start, info, npy)
            if crcs is not None:
                crcs[info.filename] = directory_record(info)
    return out


def _member_array(f, start: int, info, npy) -> np.ndarray:
    """The array of the member ``info`` whose bytes begin at ``start`` of ``f`` (a .npy
    header, then the data), its CRC-32 checked."""
    import zlib

    version = npy.read_magic(f)
    if version not in ((1, 0), (2, 0)):
        raise ValueError(f"{info.filename}: .npy version {version}")
    header = npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
    shape, fortran, dtype = header(f)
    if dtype.hasobject:
        raise ValueError(f"{info.filename}: object array")
    head = f.tell() - start
    if head + int(np.prod(shape, dtype=np.int64)) * dtype.itemsize != info.file_size:  # before allocating it
        raise ValueError(f"{info.filename}: its size is not its header's")
    array = np.empty(shape, dtype, order="F" if fortran else "C")
    data = array.reshape(-1, order="A").data.cast("B") if array.size else memoryview(b"")
    if data.nbytes and f.readinto(data) != data.nbytes:
        raise ValueError(f"{info.filename}: shorter than its header says")
    f.seek(start)
    crc = zlib.crc32(data, zlib.crc32(f.read(head)))
    if crc != info.CRC:
        raise ValueError(f"{info.filename}: CRC-32 differs")
    return array


def _entry(arrays: dict[str, np.ndarray], m: dict):
    """(UnitFields, UnitSolve) from an entry's arrays and metadata ``m``; ValueError when
    the arrays are not those the entry was written with."""
    if sorted(arrays) != m["arrays"]:
        raise ValueError("the entry's arrays are not those it was written with")
    fields = UnitFields(
        arrays["stress"],
        arrays["tip"],
        arrays["displacement"],
        arrays["nodes"],
        arrays["verdict_mask"],
        tuple(str(n) for n in arrays["names"]),
        arrays.get("cells"),
        arrays.get("support"),
        arrays.get("loaded"),
    )
    tips = {_literal(str(arrays[f"tip{i}_key"])): arrays[f"tip{i}"] for i in range(len(arrays)) if f"tip{i}" in arrays}
    if tips:
        fields = replace(fields, tips=tips)
    modes = None
    if "modes_hz" in arrays:
        count = arrays["modes_hz"].size
        modes = DynamicModel(hz=arrays["modes_hz"], shapes=np.zeros((0, count)), modal_loads=arrays["modes_loads"])
    sets = None
    if m["mode_sets"]:
        sets = {}
        i = 0
        while f"set{i}_key" in arrays:
            key = _literal(str(arrays[f"set{i}_key"]))
            hz = arrays[f"set{i}_hz"]
            sets[key] = DynamicModel(hz=hz, shapes=np.zeros((0, hz.size)), modal_loads=arrays[f"set{i}_loads"])
            i += 1
    solve = UnitSolve(
        dofs=m["dofs"],
        elements=m["elements"],
        vertices=m["vertices"],
        solver=m["solver"],
        seconds={},
        resultants=arrays["resultants"],
        support_reactions=arrays["support_reactions"],
        imbalance=arrays.get("imbalance"),
        modes=modes,
        mode_sets=sets,
    )
    return fields, solve


def _literal(text: str):
    import ast

    return ast.literal_eval(text)


def _entries(directory: Path) -> list[Path]:
    """The store's entries: regular files named as entries, not temporaries (a dangling
    link, a folder, a foreign file or one that cannot be looked at is none)."""
    if not directory.is_dir():
        return []
    return [p for p in directory.glob("*.npz") if ENTRY_NAME.fullmatch(p.name) and _is_file(p)]


def _is_file(path: Path) -> bool:
    try:
        return path.is_file()
    except OSError:
        return False


def file_size(path: Path) -> int:
    """``path``'s size in bytes, 0 when it cannot be read (gone, a dangling link, no access)."""
    try:
        return path.stat().st_size
    except OSError:
        return 0


def evict(directory: Path, cap: int, keep: Path | None = None) -> None:
    """Remove the least recently used entries until the store holds at most ``cap`` bytes
    (never ``keep``, the entry just written)."""
    try:
        entries = sorted(_entries(directory), key=lambda p: p.stat().st_mtime)
        total = sum(p.stat().st_size for p in entries)
    except OSError:
        return
    for p in entries:
        if total <= cap:
            return
        if (keep is not None and p == keep) or not is_own_entry(p, ENTRY_NAME):
            continue
        try:
            size = p.stat().st_size
            p.unlink()
            total -= size
        except OSError:
            continue


def solve_stored(request: UnitRequest, solver: str = "auto", report=None, store: UnitStore | None = None):
    """:func:`railcheck.fea.unitcases.solve_unit_cases` through ``store``: the stored
    fields when an entry for ``request`` is sound, else solved and stored (``store``
    None: solved, nothing stored). Returns
    (fields, solve, origin): ``origin`` says where the fields came from ("stored",
    "solved", or why a stored entry was solved again and why the new one is not stored:
    :func:`solved_origin`)."""
    r = request
    args = (MeshData.of(r.points, r.tets, r.groups), r.material, r.supports, r.cases)
    kw = {"order": r.order, "tip_group": r.tip_group, "exclude_distance": r.exclude, "solver": solver, "report": report}
    kw |= {"curved": r.curved, "free_body": r.free_body, "modes": r.modes}
    if store is None:
        return (*solve_unit_cases(*args, **kw), "solved")
    t = time.perf_counter()
    payload = r.payload()
    path = r.path(store, payload)
    found, why = _read_once(path, payload)
    if found is not None:
        fields, solve = found
        return fields, replace(solve, seconds={"store": time.perf_counter() - t}), "stored"
    fields, solve = solve_unit_cases(*args, **kw)
    return fields, solve, solved_origin(why, write_entry(path, payload, fields, solve, store.cap))


_SHARED: dict | None = None  # (path, payload) -> a sound entry's (fields, solve), inside reads_shared()
_SHARED_LOCK = threading.Lock()


@contextmanager
def reads_shared():
    """Inside the block (this process, any thread) a sound entry read once is not read
    again: a check's coupler and rocker rails, one size, project their settings from one
    hole basis (166 MB read and its CRC checked once, not twice). The entries' arrays are
    shared, so nothing may write into them (nothing does: a projection makes new ones).
    Forgotten when the block ends."""
    global _SHARED
    with _SHARED_LOCK:
        outer = _SHARED
        _SHARED = {} if outer is None else outer
    try:
        yield
    finally:
        with _SHARED_LOCK:
            _SHARED = outer


def _read_once(path: Path, payload: str):
    """:func:`read_entry`, or inside :func:`reads_shared` the entry already read."""
    key = (str(path), payload)
    with _SHARED_LOCK:
        shared = _SHARED
        if shared is not None and key in shared:
            return shared[key], None
    found, why = read_entry(path, payload)
    if shared is not None and found is not None:
        with _SHARED_LOCK:
            shared[key] = found
    return found, why


def is_stored(request: UnitRequest, store: UnitStore | None) -> bool:
    """Whether an entry for ``request`` is on disk in ``store`` (not yet verified:
    reading verifies); never without a store."""
    return store is not None and request.path(store).is_file()


@dataclass(frozen=True)
class StoreInfo:
    """The store's directory, entry count, bytes and cap."""

    directory: Path
    entries: int
    bytes: int
    cap: int


def store_info(store: UnitStore) -> StoreInfo:
    """What ``store`` holds: its folder, entries, bytes and cap."""
    directory = store.directory
    entries = _entries(directory)
    return StoreInfo(directory, len(entries), sum(file_size(p) for p in entries), store.cap)


def clear_store(store: UnitStore) -> tuple[int, list[str]]:
    """Remove every entry of ``store`` railcheck wrote (and dead runs' temporaries);
    (entries removed, names of the files left: what railcheck did not write). A store
    folder that is a link is not followed (nothing removed, its name left)."""
    directory = store.directory
    if directory.is_symlink():
        return 0, [directory.name + " (a link: not followed)"]
    return clear_entries(directory, ENTRY_NAME, known=frozenset({KEY_FILE}))
