"""gmsh meshing of the parts, returning plain numpy arrays, cached on disk.

gmsh is imported inside :func:`build_mesh` only. The mesh's vertices and
tetrahedra are the same for P1 and P2. A size field refines
the mesh at every hole (to ``hole_size``) and grows to ``size`` away from them.

For quadratic (P2) elements gmsh also places the mid-edge nodes on the true CAD surfaces
(``setOrder(2)``); the mesh keeps only the edges that came out curved
(:attr:`MeshData.curved`); where one folds a thin element (beside a rail's grooves) the
mid nodes round it are moved (:mod:`railcheck.geometry.untangling`, deterministic: the same
bytes every run), and what still folds is straightened (:mod:`railcheck.geometry.curving`).

The vertices are numbered by reverse Cuthill-McKee and the tetrahedra sorted by their
lowest vertex (:func:`local_numbering`), so that neighbours sit close in every array the
FE builds: on a 1M-DOF cantilever this makes assembly 1.2x and the iterative solve 1.25x
faster than with gmsh's own numbering (``benchmarks/fe_stages.py``).

Meshes are cached (:mod:`.cache`) keyed by a hash of the part's parameters, the mesh
sizes, gmsh's version and this module's; the shapes are built by :mod:`.shapes`.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from railcheck.base.code import code_hash
from railcheck.base.errors import NumericalError

from . import shapes
from .cache import default_cache_dir, read_cached, write_cached
from .curving import curved_from_tet10, straighten_folded
from .meshdata import MeshData
from .models import PartGeometry
from .shapes import BUILDERS
from .untangling import untangle

#: the set of shipped meshes (:data:`SHIPPED_DIR`): data built once by benchmarks/ship_meshes.py and
#: held to the mesher's output by tests/test_shipped_meshes.py, so their keys leave the code out; a
#: cached mesh's key carries the mesher's code hash (:func:`railcheck.base.code.code_hash`) instead
SHIPPED_SET = 14
SLIVER_SICN = 0.05  # elements whose signed inverse condition number is below this are slivers


def _gmsh_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("gmsh")
    except PackageNotFoundError:
        return "unknown"


def _cache_payload(part: PartGeometry, size: float, hole_size: float, optimize: bool = True, shipped: bool = False) -> str:
    """Everything a cached mesh depends on, as canonical JSON (stored beside the arrays); a
    shipped mesh's (:data:`SHIPPED_DIR`) leaves out the installed gmsh's version: it is the
    mesh itself, whichever gmsh reads the scene."""
    return json.dumps(
        {
            "v": SHIPPED_SET if shipped else code_hash("railcheck.geometry"),
            "gmsh": "shipped" if shipped else _gmsh_version(),
            "kind": part.kind,
            "params": [list(p) for p in part.params],
            "size": size,
            "hole_size": hole_size,
            "optimize": optimize,
            "grooves": [shapes.GROOVE_ELEMENT_PER_RADIUS, UNTANGLE] if dict(part.params).get("groove_radius") else None,
        },
        sort_keys=True,
        default=list,
    )


def _cache_key(part: PartGeometry, size: float, hole_size: float, optimize: bool = True, shipped: bool = False) -> str:
    return hashlib.sha256(_cache_payload(part, size, hole_size, optimize, shipped).encode()).hexdigest()[:24]


#: meshes shipped with railcheck: the rig's parts at their default sizes, built once (a
#: grooved rail's untangling is not reproducible run to run, so every user and every cold
#: run reads the same mesh; and a cold check skips its slowest stage). Read before the
#: cache: where one is shipped, it is the mesh.
SHIPPED_DIR = Path(__file__).parent / "meshes"


def shipped_entry(part: PartGeometry, size: float, hole_size: float, optimize: bool = True) -> tuple[Path, str]:
    """(path, payload) of the shipped mesh of ``part`` at these parameters (it may not exist)."""
    key = _cache_key(part, size, hole_size, optimize, shipped=True)
    return SHIPPED_DIR / f"{part.kind}-{key}.npz", _cache_payload(part, size, hole_size, optimize, shipped=True)


def shipped_mesh(part: PartGeometry, size: float, hole_size: float, optimize: bool = True) -> MeshData | None:
    """The mesh shipped with railcheck for these parameters, or None (none shipped; a
    damaged one is ignored: the part is meshed)."""
    data = read_cached(*shipped_entry(part, size, hole_size, optimize))[0]
    if data is None:
        return None
    from dataclasses import replace

    return replace(data, shipped=True)


def write_shipped_mesh(part: PartGeometry, size: float, hole_size: float, optimize: bool = True) -> Path:
    """Mesh ``part`` afresh and store it among the shipped meshes (a maintainer's step:
    ``benchmarks/ship_meshes.py``); returns its path."""
    path, payload = shipped_entry(part, size, hole_size, optimize)
    write_cached(path, build_mesh(part, size, hole_size, optimize=optimize), payload, compressed=True)
    return path


#: tetrahedra per surface triangle of a rail's grooves at their own element size
#: (:data:`shapes.GROOVE_ELEMENT_PER_RADIUS` x the radius): the refined layer under a finer
#: surface; fitted to the shipped rails (8.3 on the 1 m, 9.7 on the 0.7 m rail at the
#: defaults), 9 predicts the 0.5 mm grooves' 104,505 elements of the 0.7 m rail to 15%
GROOVE_TETS_PER_TRIANGLE = 9.0


def estimate_elements(part: PartGeometry, size: float, hole_size: float) -> int:
    """A rough count of tetrahedra for the part at these sizes (for refusing huge runs
    before meshing): about 6 V / h^3, plus the refined shells around the holes, plus the
    refined layer under a rail's grooves (:data:`GROOVE_TETS_PER_TRIANGLE` per surface
    element of their four half-cylinders). Within about 30% of the shipped meshes."""
    n = 6.0 * part.volume / size**3
    holes = sum(1 for g in part.groups if g.startswith("hole_") or g in ("bearing_seat",))
    p: dict[str, Any] = dict(part.params)
    thickness = p.get("height", p.get("thickness", p.get("depth", size)))
    shell = math.pi * (size**2) * thickness  # a shell about one size thick round each hole
    n += holes * 6.0 * shell / hole_size**3
    radius = float(p.get("groove_radius") or 0.0)
    if radius > 0:
        h = min(size, shapes.GROOVE_ELEMENT_PER_RADIUS * radius)
        n += GROOVE_TETS_PER_TRIANGLE * 4.0 * math.pi * radius * float(p.get("length", 0.0)) / h**2
    return int(n)


def mesh_part(
    part: PartGeometry,
    size: float,
    hole_size: float | None = None,
    cache: bool = True,
    cache_dir: Path | None = None,
    verbose: bool = False,
    optimize: bool = True,
) -> MeshData:
    """Mesh ``part`` with element size ``size`` (m), ``hole_size`` at the holes (default
    size / 3); read from / write to the cache unless ``cache`` is False. A cache entry
    stores its parameters (gmsh version included) and a content hash, both verified on
    load: a damaged or mismatched entry is rebuilt and ``MeshData.warning`` says why, as
    it says when the cache cannot keep the new entry (a full disk).
    ``optimize`` False skips gmsh's tetrahedron optimisation (slivers may remain; they are
    counted). gmsh prints nothing unless ``verbose``. ``cache_dir``: the cache's folder
    (default :func:`~railcheck.geometry.cache.default_cache_dir`)."""
    hole_size = hole_size or size / 3.0
    path, payload = _cache_entry(part, size, hole_size, optimize, cache_dir)
    why = None
    if cache:
        data = shipped_mesh(part, size, hole_size, optimize)  # the one mesh every run reads
        if data is not None:
            return data
        data, why = read_cached(path, payload)
        if data is not None:
            return data
    data = build_mesh(part, size, hole_size, verbose=verbose, optimize=optimize)
    unwritten = write_cached(path, data, payload) if cache else None
    said = [
        f"cached mesh {path.name} {why}: rebuilt" if why else None,
        f"mesh not cached ({unwritten}): the next run meshes it again" if unwritten else None,
    ]
    if any(said):  # beside the mesher's own warning (stored with the entry), not instead of it
        from dataclasses import replace

        data = replace(data, warning="; ".join(w for w in (data.warning, *said) if w))
    return data


def cached_mesh(
    part: PartGeometry,
    size: float,
    hole_size: float | None = None,
    optimize: bool = True,
    cache_dir: Path | None = None,
) -> MeshData | None:
    """The mesh :func:`mesh_part` would read from the cache in ``cache_dir``, or None when
    it would have to build it (no entry, or a damaged or stale one): a probe that never
    meshes; a mesh shipped with railcheck counts as cached."""
    hole_size = hole_size or size / 3.0
    shipped = shipped_mesh(part, size, hole_size, optimize)
    return shipped if shipped is not None else read_cached(*_cache_entry(part, size, hole_size, optimize, cache_dir))[0]


def _cache_entry(
    part: PartGeometry, size: float, hole_size: float, optimize: bool, cache_dir: Path | None = None
) -> tuple[Path, str]:
    """(path, payload) of the cache entry of ``part`` meshed with these parameters."""
    payload = _cache_payload(part, size, hole_size, optimize)
    return (cache_dir or default_cache_dir()) / f"{part.kind}-{_cache_key(part, size, hole_size, optimize)}.npz", payload


def build_mesh(part: PartGeometry, size: float, hole_size: float, verbose: bool = False, optimize: bool = True) -> MeshData:
    """Build the gmsh model of ``part`` and mesh it (no cache).

    gmsh's ``initialize`` resets SIGTERM to the default action (it kills the process) until
    the caller's handler is put back, and blocking the signal in the calling thread only
    sends it to another thread (numpy's and MKL's). A caller that handles SIGTERM (the
    command line: a terminated run removes its staging directory) therefore gets its mesh
    from a child process, where gmsh cannot touch the caller's handlers; the child costs
    about 0.2 s. So does a caller in another thread than the main one, where the caller's
    handlers (and Python's ignored SIGPIPE) cannot be put back. Any other caller meshes in
    this process."""
    if _handles_sigterm() or threading.current_thread() is not threading.main_thread():
        return _build_in_child(part, size, hole_size, verbose, optimize)
    return _build_here(part, size, hole_size, verbose, optimize)


class MeshFailure(NumericalError):
    """gmsh could not mesh a part with the scene's mesh sizes (exit 3); the field is the
    ``[mesh]`` table, whose sizes are what the user can change."""


def _handles_sigterm() -> bool:
    import signal

    return callable(signal.getsignal(signal.SIGTERM))


def _build_in_child(part: PartGeometry, size: float, hole_size: float, verbose: bool, optimize: bool) -> MeshData:
    """:func:`_build_here` in a child process; its exception, if any, is raised here. An
    exception here (SIGTERM, Ctrl-C) kills the child (``subprocess.run``); a child that
    dies is a :class:`MeshFailure`."""
    return _child_result(_run_child(part, size, hole_size, verbose, optimize), verbose)


def _run_child(part: PartGeometry, size: float, hole_size: float, verbose: bool, optimize: bool):
    """The finished child process meshing ``part`` (``subprocess.CompletedProcess``)."""
    import pickle
    import subprocess
    import sys

    tunables = {  # as a benchmark or a test may have set them
        "shapes.GROOVE_ELEMENT_PER_RADIUS": shapes.GROOVE_ELEMENT_PER_RADIUS,
        "mesher.UNTANGLE": UNTANGLE,
    }
    request = pickle.dumps((part, size, hole_size, verbose, optimize, tunables))
    code = f"from railcheck.geometry.mesher import _child_main; _child_main({os.getpid()})"
    return subprocess.run([sys.executable, "-P", "-c", code], input=request, capture_output=True, check=False)


def _last_line(proc) -> str:
    """The last line a dead child printed (gmsh's error), or its exit status."""
    lines = proc.stderr.decode(errors="replace").strip().splitlines()
    return lines[-1].strip() if lines else f"exit status {proc.returncode}"


def _child_result(proc, verbose: bool) -> MeshData:
    """The mesh a child sent back, its exception raised here, or a :class:`MeshFailure`
    for a child that died."""
    import pickle
    import sys

    if proc.returncode != 0 or not proc.stdout:
        why = _last_line(proc)
        raise MeshFailure(f"gmsh could not mesh the part with these sizes ({why}); try another size or hole_size", "mesh")
    if verbose and proc.stderr:
        sys.stderr.write(proc.stderr.decode(errors="replace"))
    ok, value = pickle.loads(proc.stdout)
    if not ok:
        raise value
    return value


def die_with_parent(parent: int) -> None:
    """Have the kernel kill this process when its parent ``parent`` (a pid) dies, as a
    ``kill -9`` of a check does (Linux's PR_SET_PDEATHSIG; elsewhere nothing), and exit
    now if it already has: a mesh nobody waits for is not built to its end."""
    import ctypes
    import signal
    import sys

    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # 1: PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:
        os._exit(1)


def _child_main(parent: int | None = None) -> None:
    """The child of :func:`_build_in_child`: the request from stdin, ``(ok, mesh or
    exception)`` pickled to stdout; gmsh's own terminal output goes to stderr. It dies
    with its ``parent`` (:func:`die_with_parent`)."""
    import pickle
    import sys

    if parent is not None:
        die_with_parent(parent)

    result_fd = os.dup(1)
    os.dup2(2, 1)
    part, size, hole_size, verbose, optimize, tunables = pickle.loads(sys.stdin.buffer.read())
    for name, value in tunables.items():
        module, attribute = name.split(".")
        setattr(shapes if module == "shapes" else sys.modules[__name__], attribute, value)
    try:
        reply: tuple[bool, object] = (True, _build_here(part, size, hole_size, verbose, optimize))
    except Exception as exc:  # noqa: BLE001 - handed to the parent, which raises it
        reply = (False, exc)
    with os.fdopen(result_fd, "wb") as out:
        out.write(pickle.dumps(reply))


def _size_field(gmsh, size: float, hole_size: float, optimize: bool, refine, fine: dict) -> None:
    """gmsh's mesh options and size field (m): ``hole_size`` on the ``refine`` surfaces,
    at most each cap of ``fine`` (cap -> surfaces) on its surfaces, growing to ``size``;
    Delaunay, one thread (deterministic meshes), optimised when ``optimize``."""
    # size field: hole_size on the refined surfaces, growing to size
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", min(size, hole_size) * 0.5)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
    gmsh.option.setNumber("Mesh.Optimize", 1 if optimize else 0)
    gmsh.option.setNumber("General.NumThreads", 1)  # deterministic meshes
    fields = []
    if refine and hole_size < size:
        fields.append(_threshold_field(gmsh, refine, hole_size, size))
    for cap, tags in fine.items():  # surfaces whose curvature asks for at most ``cap``
        if min(cap, hole_size) < size:
            gmsh.option.setNumber("Mesh.MeshSizeMin", min(size, hole_size, cap) * 0.5)
            fields.append(_threshold_field(gmsh, tags, min(cap, hole_size), size))
    if len(fields) == 1:
        gmsh.model.mesh.field.setAsBackgroundMesh(fields[0])
    elif fields:
        fm = gmsh.model.mesh.field.add("Min")
        gmsh.model.mesh.field.setNumbers(fm, "FieldsList", fields)
        gmsh.model.mesh.field.setAsBackgroundMesh(fm)


def _build_here(part: PartGeometry, size: float, hole_size: float, verbose: bool, optimize: bool) -> MeshData:
    """Build and mesh ``part`` with gmsh in this process."""
    t0 = time.perf_counter()
    with _callers_signal_handlers() as restore:
        import gmsh

        gmsh.initialize(interruptible=False)
        restore()
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
        gmsh.option.setNumber("General.Verbosity", 5 if verbose else 0)
        gmsh.model.add(part.kind)
        surfaces, refine, *extra = BUILDERS[part.kind](gmsh, dict(part.params))
        fine: dict = extra[0] if extra else {}
        vols = gmsh.model.getEntities(3)
        gmsh.model.addPhysicalGroup(3, [v[1] for v in vols], name="solid")
        for name, tags in surfaces.items():
            if not tags:
                raise RuntimeError(f"geometry: group {name!r} found no surface")
            gmsh.model.addPhysicalGroup(2, sorted(set(tags)), name=name)
        _size_field(gmsh, size, hole_size, optimize, refine, fine)
        gmsh.model.mesh.generate(3)
        qualities = _qualities(gmsh)
        curved = _has_curved_surfaces(gmsh)
        if curved:
            gmsh.model.mesh.setOrder(2)  # mid-edge nodes on the CAD surfaces
        data, index = _extract(gmsh, surfaces, qualities)
        if curved:
            data = _with_curved_edges(gmsh, data, index)
        from dataclasses import replace

        return replace(data, seconds=time.perf_counter() - t0)
    finally:
        with _callers_signal_handlers() as restore:
            gmsh.finalize()
            restore()


#: untangle folded curved elements (geometry.untangling; False only to measure what it buys)
UNTANGLE = True


def _threshold_field(gmsh, surfaces, near: float, far: float) -> int:
    """A size field: ``near`` (m) within ``near`` of the ``surfaces``, growing to ``far``
    over two ``far`` lengths."""
    fd = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(fd, "SurfacesList", sorted(set(surfaces)))
    gmsh.model.mesh.field.setNumber(fd, "Sampling", 40)
    ft = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(ft, "InField", fd)
    gmsh.model.mesh.field.setNumber(ft, "SizeMin", near)
    gmsh.model.mesh.field.setNumber(ft, "SizeMax", far)
    gmsh.model.mesh.field.setNumber(ft, "DistMin", near)
    gmsh.model.mesh.field.setNumber(ft, "DistMax", near + 2.0 * far)
    return ft


@contextlib.contextmanager
def _callers_signal_handlers():
    """gmsh (its library's loading, initialize and finalize) installs its own SIGINT and
    SIGTERM handlers and sets SIGPIPE back to the default action: keep the caller's
    (SIGTERM cleans up a run; Python ignores SIGPIPE, so that a write to a closed pipe is an
    error, not the death of the process: a forked pool's stopped children, ``| head``).
    SIGINT and SIGTERM are held back in the block, so one that arrives meanwhile reaches
    the caller's handler once ``restore()`` has put it back, instead of gmsh's or the
    default action."""
    import signal

    wanted = (signal.SIGINT, signal.SIGTERM)
    handlers = {sig: signal.getsignal(sig) for sig in (*wanted, signal.SIGPIPE)}
    main = threading.current_thread() is threading.main_thread()

    def restore():
        if main:
            for sig, handler in handlers.items():
                signal.signal(sig, handler)

    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, wanted)
    try:
        yield restore
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)


def _has_curved_surfaces(gmsh) -> bool:
    return any(gmsh.model.getType(dim, tag) != "Plane" for dim, tag in gmsh.model.getEntities(2))


GMSH_TET10_EDGE_COLUMNS = [4, 5, 6, 7, 9, 8]
TET_NODES = {4: 4, 11: 10}  # gmsh element type -> nodes (linear, quadratic tetrahedron)
TRI_NODES = {2: 3, 9: 6}  # gmsh's mid nodes in curving.LOCAL_EDGES order


def _qualities(gmsh) -> np.ndarray:
    """gmsh's minSICN of every (linear) tetrahedron."""
    _, etags, _ = gmsh.model.mesh.getElements(3)
    return gmsh.model.mesh.getElementQualities(np.concatenate(etags), "minSICN")


def _with_curved_edges(gmsh, data: MeshData, index: np.ndarray) -> MeshData:
    """From gmsh's second-order mesh: keep the edges that came out curved, untangle the
    elements they fold (:func:`untangle`) and straighten any element that still would."""
    from dataclasses import replace

    tags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = np.zeros((int(tags.max()) + 1, 3))
    xyz[tags] = coords.reshape(-1, 3)
    etypes, _, enodes = gmsh.model.mesh.getElements(3)
    t10 = np.concatenate([n.astype(np.int64).reshape(-1, 10) for et, n in zip(etypes, enodes) if et == 11])
    tets = index[t10[:, :4]]
    mids = xyz[t10[:, GMSH_TET10_EDGE_COLUMNS]]
    edges, points = curved_from_tet10(data.points, tets, mids)
    if UNTANGLE:
        edges, points = untangle(data.points, tets, edges, points)
    edges, points, dropped = straighten_folded(data.points, tets, edges, points)
    warning = (
        f"{dropped} curved edges straightened to keep elements from folding "
        f"({dropped / max(dropped + edges.shape[0], 1):.1%} of the curved edges; the surface is faceted there)"
        if dropped
        else None
    )
    return replace(data, curved_edges=edges, curved_points=points, warning=warning)


def _extract(gmsh, surfaces, qualities: np.ndarray) -> tuple[MeshData, np.ndarray]:
    """(mesh, index): the linear mesh (the vertices of first- or second-order elements),
    and the map from gmsh node tag to point index."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags)
    tags = tags[order]
    points = coords.reshape(-1, 3)[order]
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags] = np.arange(tags.size)
    etypes, etags, enodes = gmsh.model.mesh.getElements(3)
    blocks = []
    for et, nn in zip(etypes, enodes):
        if et not in TET_NODES:
            raise RuntimeError(f"unexpected 3D element type {et}")
        blocks.append(index[nn.astype(np.int64)].reshape(-1, TET_NODES[et])[:, :4])
    tets = np.concatenate(blocks)
    groups = {}
    for name, stags in surfaces.items():
        tris = []
        for s in sorted(set(stags)):
            et, _, nn = gmsh.model.mesh.getElements(2, s)
            for etype, n in zip(et, nn):
                tris.append(index[n.astype(np.int64)].reshape(-1, TRI_NODES[etype])[:, :3])
        groups[name] = np.concatenate(tris)
    used = np.unique(tets)
    if used.size != points.shape[0]:  # drop nodes no tetrahedron uses (geometry points)
        remap = np.full(points.shape[0], -1, dtype=np.int64)
        remap[used] = np.arange(used.size)
        points = points[used]
        tets = remap[tets]
        groups = {k: remap[v] for k, v in groups.items()}
        index = np.where(index >= 0, remap[np.maximum(index, 0)], -1)
    new, tets = local_numbering(tets, points.shape[0])
    points[new] = points.copy()
    groups = {k: new[v] for k, v in groups.items()}
    index = np.where(index >= 0, new[np.maximum(index, 0)], -1)
    return MeshData(
        points, tets.astype(np.int64), groups, float(qualities.min()), int(np.count_nonzero(qualities < SLIVER_SICN)), 0.0
    ), index


def local_numbering(tets: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(new, tets): each vertex's new number (n,) by reverse Cuthill-McKee on the vertex
    graph, and the tetrahedra (m, 4) renumbered and sorted by their lowest new vertex."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    rows = np.repeat(tets, 4, axis=1).ravel()
    cols = np.tile(tets, (1, 4)).ravel()
    graph = sp.csr_matrix((np.ones(rows.size, np.int8), (rows, cols)), shape=(n, n))
    order = reverse_cuthill_mckee(graph, symmetric_mode=True)
    new = np.empty(n, dtype=np.int64)
    new[order] = np.arange(n)
    tets = new[tets]
    return new, tets[np.argsort(tets.min(axis=1), kind="stable")]


# --- builders: each returns ({group: [surface tags]}, [surface tags to refine at]) and,
# optionally, {largest element size m: [surface tags]} for curved surfaces that need it ---
