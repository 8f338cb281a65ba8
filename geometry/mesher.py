"""gmsh meshing of the parts, returning plain numpy arrays, cached on disk.

gmsh is imported inside :func:`build_mesh` only. The mesh's vertices and
tetrahedra are the same for P1 and P2. A size field refines
the mesh at every hole (to ``hole_size``) and grows to ``size`` away from them.

For quadratic (P2) elements gmsh also places the mid-edge nodes on the true CAD surfaces
(``setOrder(2)``); the mesh keeps only the edges that came out curved
(:attr:`MeshData.curved`), checked for folded elements (:mod:`geometry.curving`).

The vertices are numbered by reverse Cuthill-McKee and the tetrahedra sorted by their
lowest vertex (:func:`local_numbering`), so that neighbours sit close in every array the
FE builds: on a 1M-DOF cantilever this makes assembly 1.2x and the iterative solve 1.25x
faster than with gmsh's own numbering (``benchmarks/fe_stages.py``).

Meshes are cached in ``$RAILCHECK_CACHE`` (default ``~/.cache/railcheck``) keyed by a hash
of the part's parameters, the mesh sizes and this module's version.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .models import PartGeometry

MESHER_VERSION = 8
SLIVER_SICN = 0.05   # elements whose signed inverse condition number is below this are slivers


@dataclass(frozen=True)
class MeshData:
    """A tetrahedral mesh: ``points`` (n, 3) m, ``tets`` (m, 4) node indices, and named
    boundary groups ``groups[name]`` = (k, 3) triangle node indices. ``min_quality`` is
    gmsh's smallest minSICN over the elements, ``slivers`` how many fall below
    :data:`SLIVER_SICN`; ``seconds`` the meshing time (0 when read from the cache)."""

    points: np.ndarray
    tets: np.ndarray
    groups: dict[str, np.ndarray]
    min_quality: float
    slivers: int
    seconds: float
    cached: bool = False
    warning: str | None = None
    curved_edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    curved_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def curved(self) -> tuple[np.ndarray, np.ndarray]:
        """(edges (k, 2), mid-edge points (k, 3) m): the quadratic mesh's curved edges
        (mid nodes on the true surfaces); every other edge of a P2 mesh is straight."""
        return self.curved_edges, self.curved_points


def default_cache_dir() -> Path:
    return Path(os.environ.get("RAILCHECK_CACHE", Path.home() / ".cache" / "railcheck"))


def _gmsh_version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("gmsh")
    except PackageNotFoundError:
        return "unknown"


def _cache_payload(part: PartGeometry, size: float, hole_size: float, optimize: bool = True) -> str:
    """Everything a cached mesh depends on, as canonical JSON (stored beside the arrays)."""
    return json.dumps({"v": MESHER_VERSION, "gmsh": _gmsh_version(), "kind": part.kind,
                       "params": [list(p) for p in part.params], "size": size, "hole_size": hole_size,
                       "optimize": optimize}, sort_keys=True, default=list)


def _cache_key(part: PartGeometry, size: float, hole_size: float, optimize: bool = True) -> str:
    return hashlib.sha256(_cache_payload(part, size, hole_size, optimize).encode()).hexdigest()[:24]


def _digest(points: np.ndarray, tets: np.ndarray, groups: dict[str, np.ndarray],
            curved: tuple[np.ndarray, np.ndarray]) -> str:
    """SHA-256 of the mesh arrays' bytes (with the group names): the cache entry's content hash."""
    h = hashlib.sha256()
    for a in (points, tets, *curved):
        h.update(np.ascontiguousarray(a).tobytes())
    for name in sorted(groups):
        h.update(name.encode())
        h.update(np.ascontiguousarray(groups[name]).tobytes())
    return h.hexdigest()


def estimate_elements(part: PartGeometry, size: float, hole_size: float) -> int:
    """A rough count of tetrahedra for the part at these sizes (for refusing huge runs
    before meshing): about 6 V / h^3, plus the refined shells around the holes."""
    n = 6.0 * part.volume / size**3
    holes = sum(1 for g in part.groups if g.startswith("hole_") or g in ("bearing_seat",))
    p = dict(part.params)
    thickness = p.get("height", p.get("thickness", p.get("depth", size)))
    shell = math.pi * (size**2) * thickness          # a shell about one size thick round each hole
    n += holes * 6.0 * shell / hole_size**3
    return int(n)


def read_cached(path: Path, payload: str) -> tuple[MeshData | None, str | None]:
    """(mesh, None) for a sound cache entry of these parameters; (None, why) for a missing,
    damaged, swapped or stale one."""
    if not path.exists():
        return None, None
    try:
        with np.load(path, allow_pickle=False) as z:
            stored_payload, stored_digest = str(z["payload"]), str(z["digest"])
            points, tets = z["points"], z["tets"]
            groups = {k[2:]: z[k] for k in z.files if k.startswith("g_")}
            quality, slivers = float(z["min_quality"]), int(z["slivers"])
            curved = (z["curved_edges"], z["curved_points"])
    except Exception as exc:   # noqa: BLE001 - any unreadable file is a damaged entry
        return None, f"unreadable ({type(exc).__name__})"
    if stored_payload != payload:
        return None, "made for other parameters"
    if stored_digest != _digest(points, tets, groups, curved):
        return None, "content does not match its hash"
    return MeshData(points, tets, groups, quality, slivers, 0.0, cached=True, curved_edges=curved[0],
                    curved_points=curved[1]), None


def write_cached(path: Path, data: MeshData, payload: str) -> None:
    """Write a cache entry atomically (a per-process temporary name, then a rename), so
    concurrent runs never read half a file; an unwritable cache only costs time."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.npz")
        np.savez(tmp, points=data.points, tets=data.tets, min_quality=data.min_quality, slivers=data.slivers,
                 curved_edges=data.curved_edges, curved_points=data.curved_points, payload=np.array(payload),
                 digest=np.array(_digest(data.points, data.tets, data.groups, data.curved)),
                 **{f"g_{k}": v for k, v in data.groups.items()})
        os.replace(tmp, path)
    except OSError:
        pass


def mesh_part(part: PartGeometry, size: float, hole_size: float | None = None,
              cache: bool = True, cache_dir: Path | None = None, verbose: bool | None = None,
              optimize: bool = True) -> MeshData:
    """Mesh ``part`` with element size ``size`` (m), ``hole_size`` at the holes (default
    size / 3); read from / write to the cache unless ``cache`` is False. A cache entry
    stores its parameters (gmsh version included) and a content hash, both verified on
    load: a damaged or mismatched entry is rebuilt and ``MeshData.warning`` says why.
    ``optimize`` False skips gmsh's tetrahedron optimisation (slivers may remain; they are
    counted). gmsh prints nothing unless ``verbose`` or ``RAILCHECK_GMSH_VERBOSE=1``."""
    if verbose is None:
        verbose = os.environ.get("RAILCHECK_GMSH_VERBOSE", "") not in ("", "0")
    hole_size = hole_size or size / 3.0
    payload = _cache_payload(part, size, hole_size, optimize)
    path = (cache_dir or default_cache_dir()) / f"{part.kind}-{_cache_key(part, size, hole_size, optimize)}.npz"
    why = None
    if cache:
        data, why = read_cached(path, payload)
        if data is not None:
            return data
    data = build_mesh(part, size, hole_size, verbose=verbose, optimize=optimize)
    if cache:
        write_cached(path, data, payload)
    if why:
        from dataclasses import replace
        data = replace(data, warning=f"cached mesh {path.name} {why}: rebuilt")
    return data


def build_mesh(part: PartGeometry, size: float, hole_size: float, verbose: bool = False,
               optimize: bool = True) -> MeshData:
    """Build the gmsh model of ``part`` and mesh it (no cache)."""
    t0 = time.perf_counter()
    with _callers_signal_handlers() as restore:
        import gmsh
        gmsh.initialize(interruptible=False)
        restore()
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
        gmsh.option.setNumber("General.Verbosity", 5 if verbose else 0)
        gmsh.model.add(part.kind)
        surfaces, refine = _BUILDERS[part.kind](gmsh, dict(part.params))
        vols = gmsh.model.getEntities(3)
        gmsh.model.addPhysicalGroup(3, [v[1] for v in vols], name="solid")
        for name, tags in surfaces.items():
            if not tags:
                raise RuntimeError(f"geometry: group {name!r} found no surface")
            gmsh.model.addPhysicalGroup(2, sorted(set(tags)), name=name)
        # size field: hole_size on the refined surfaces, growing to size
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", min(size, hole_size) * 0.5)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)       # Delaunay
        gmsh.option.setNumber("Mesh.Optimize", 1 if optimize else 0)
        gmsh.option.setNumber("General.NumThreads", 1)     # deterministic meshes
        if refine and hole_size < size:
            fd = gmsh.model.mesh.field.add("Distance")
            gmsh.model.mesh.field.setNumbers(fd, "SurfacesList", sorted(set(refine)))
            gmsh.model.mesh.field.setNumber(fd, "Sampling", 40)
            ft = gmsh.model.mesh.field.add("Threshold")
            gmsh.model.mesh.field.setNumber(ft, "InField", fd)
            gmsh.model.mesh.field.setNumber(ft, "SizeMin", hole_size)
            gmsh.model.mesh.field.setNumber(ft, "SizeMax", size)
            gmsh.model.mesh.field.setNumber(ft, "DistMin", hole_size)
            gmsh.model.mesh.field.setNumber(ft, "DistMax", hole_size + 2.0 * size)
            gmsh.model.mesh.field.setAsBackgroundMesh(ft)
        gmsh.model.mesh.generate(3)
        qualities = _qualities(gmsh)
        curved = _has_curved_surfaces(gmsh)
        if curved:
            gmsh.model.mesh.setOrder(2)     # mid-edge nodes on the CAD surfaces
        data, index = _extract(gmsh, surfaces, qualities)
        if curved:
            data = _with_curved_edges(gmsh, data, index)
        from dataclasses import replace
        return replace(data, seconds=time.perf_counter() - t0)
    finally:
        with _callers_signal_handlers() as restore:
            gmsh.finalize()
            restore()


@contextlib.contextmanager
def _callers_signal_handlers():
    """gmsh (its library's loading, initialize and finalize) installs its own SIGINT and
    SIGTERM handlers: keep the caller's (SIGTERM cleans up a run). Both signals are held
    back in the block, so one that arrives meanwhile reaches the caller's handler once
    ``restore()`` has put it back, instead of gmsh's or the default action."""
    import signal

    wanted = (signal.SIGINT, signal.SIGTERM)
    handlers = {sig: signal.getsignal(sig) for sig in wanted}
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
TET_NODES = {4: 4, 11: 10}     # gmsh element type -> nodes (linear, quadratic tetrahedron)
TRI_NODES = {2: 3, 9: 6}   # gmsh's mid nodes in curving.LOCAL_EDGES order


def _qualities(gmsh) -> np.ndarray:
    """gmsh's minSICN of every (linear) tetrahedron."""
    _, etags, _ = gmsh.model.mesh.getElements(3)
    return gmsh.model.mesh.getElementQualities(np.concatenate(etags), "minSICN")


def _with_curved_edges(gmsh, data: MeshData, index: np.ndarray) -> MeshData:
    """From gmsh's second-order mesh: keep the edges that came out curved, and
    straighten any element that would fold."""
    from dataclasses import replace

    from .curving import curved_from_tet10, straighten_folded

    tags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = np.zeros((int(tags.max()) + 1, 3))
    xyz[tags] = coords.reshape(-1, 3)
    etypes, _, enodes = gmsh.model.mesh.getElements(3)
    t10 = np.concatenate([n.astype(np.int64).reshape(-1, 10) for et, n in zip(etypes, enodes) if et == 11])
    tets = index[t10[:, :4]]
    mids = xyz[t10[:, GMSH_TET10_EDGE_COLUMNS]]
    edges, points = curved_from_tet10(data.points, tets, mids)
    edges, points, dropped = straighten_folded(data.points, tets, edges, points)
    warning = f"{dropped} curved edges straightened to keep elements from folding" if dropped else None
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
    tets = []
    for et, nn in zip(etypes, enodes):
        if et not in TET_NODES:
            raise RuntimeError(f"unexpected 3D element type {et}")
        tets.append(index[nn.astype(np.int64)].reshape(-1, TET_NODES[et])[:, :4])
    tets = np.concatenate(tets)
    groups = {}
    for name, stags in surfaces.items():
        tris = []
        for s in sorted(set(stags)):
            et, _, nn = gmsh.model.mesh.getElements(2, s)
            for etype, n in zip(et, nn):
                tris.append(index[n.astype(np.int64)].reshape(-1, TRI_NODES[etype])[:, :3])
        groups[name] = np.concatenate(tris)
    used = np.unique(tets)
    if used.size != points.shape[0]:       # drop nodes no tetrahedron uses (geometry points)
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
    return MeshData(points, tets.astype(np.int64), groups, float(qualities.min()),
                    int(np.count_nonzero(qualities < SLIVER_SICN)), 0.0), index


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


# --- builders: each returns ({group: [surface tags]}, [surface tags to refine at]) ---------

def _classify_cylinders(gmsh, centres, radius, z_range, tol):
    """Surface tags of cylindrical faces of the given ``radius`` around each (x, y) centre
    whose z extent lies in ``z_range``; one list per centre."""
    out = [[] for _ in centres]
    for dim, tag in gmsh.model.getEntities(2):
        if gmsh.model.getType(dim, tag) != "Cylinder":
            continue
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        if z0 < z_range[0] - tol or z1 > z_range[1] + tol:
            continue
        for k, (cx, cy) in enumerate(centres):
            if (x0 >= cx - radius - tol and x1 <= cx + radius + tol and y0 >= cy - radius - tol
                    and y1 <= cy + radius + tol and max(x1 - x0, y1 - y0) > radius):
                out[k].append(tag)
    return out


def _planes_at(gmsh, axis, value, tol):
    """Plane surface tags lying in the plane coordinate[axis] = value."""
    tags = []
    for dim, tag in gmsh.model.getEntities(2):
        bb = gmsh.model.getBoundingBox(dim, tag)
        if abs(bb[axis] - value) < tol and abs(bb[axis + 3] - value) < tol:
            tags.append(tag)
    return tags


def _build_bar(gmsh, p):
    L, w, h = p["length"], p["width"], p["height"]
    gmsh.model.occ.addBox(0, -w / 2, -h / 2, L, w, h)
    gmsh.model.occ.synchronize()
    return {"clamp": _planes_at(gmsh, 0, 0.0, 1e-6), "tip": _planes_at(gmsh, 0, L, 1e-6)}, []


def _build_rail(gmsh, p):
    L, w, h = p["length"], p["width"], p["height"]
    xs = p["hole_x"]
    r, rc, dc = p["hole_diameter"] / 2, p["counterbore_diameter"] / 2, p["counterbore_depth"]
    occ = gmsh.model.occ
    box = occ.addBox(0, -w / 2, 0, L, w, h)
    tools = []
    for x in xs:
        tools.append((3, occ.addCylinder(x, 0, -h, 0, 0, 3 * h, r)))
        tools.append((3, occ.addCylinder(x, 0, h - dc, 0, 0, 2 * dc, rc)))
    if tools:
        occ.cut([(3, box)], tools)
    occ.synchronize()
    holes = _classify_cylinders(gmsh, [(x, 0.0) for x in xs], r, (0.0, h - dc), 1e-7)
    cbores = _classify_cylinders(gmsh, [(x, 0.0) for x in xs], rc, (h - dc, h), 1e-7)
    groups = {"end_pivot": _planes_at(gmsh, 0, 0.0, 1e-6), "end_free": _planes_at(gmsh, 0, L, 1e-6)}
    for k, tags in enumerate(holes):
        groups[f"hole_{k}"] = tags
    if xs:
        groups["shaft_hole"] = holes[0]
    refine = [t for tags in holes + cbores for t in tags]
    return groups, refine


def _build_joint_plate(gmsh, p):
    L, W, t = p["length"], p["width"], p["thickness"]
    occ = gmsh.model.occ
    box = occ.addBox(0, -W / 2, 0, L, W, t)
    seat = occ.addCylinder(p["seat_x"], 0, -t, 0, 0, 3 * t, p["seat_diameter"] / 2)
    bolts = [occ.addCylinder(x, 0, -t, 0, 0, 3 * t, p["bolt_diameter"] / 2) for x in p["bolt_x"]]
    occ.cut([(3, box)], [(3, seat)] + [(3, b) for b in bolts])
    occ.synchronize()
    seat_tags = _classify_cylinders(gmsh, [(p["seat_x"], 0.0)], p["seat_diameter"] / 2, (0, t), 1e-7)[0]
    holes = _classify_cylinders(gmsh, [(x, 0.0) for x in p["bolt_x"]], p["bolt_diameter"] / 2, (0, t), 1e-7)
    groups = {"bearing_seat": seat_tags, "end_free": _planes_at(gmsh, 0, L, 1e-6)}
    for k, tags in enumerate(holes):
        groups[f"hole_{k}"] = tags
    return groups, seat_tags + [t_ for tags in holes for t_ in tags]


def i_profile_hole_centres(p) -> list[tuple[float, float]]:
    """(x, y) of the four top-flange holes, in the order hole_0 .. hole_3."""
    L, px, py = p["length"], p["bolt_pitch_x"], p["bolt_pitch_y"]
    return [(L / 2 - px / 2, -py / 2), (L / 2 - px / 2, py / 2), (L / 2 + px / 2, -py / 2), (L / 2 + px / 2, py / 2)]


def _build_i_profile(gmsh, p):
    L, fw, D = p["length"], p["flange_width"], p["depth"]
    tf, tw = p["flange_thickness"], p["web_thickness"]
    occ = gmsh.model.occ
    bottom = occ.addBox(0, -fw / 2, 0, L, fw, tf)
    web = occ.addBox(0, -tw / 2, tf, L, tw, D - 2 * tf)
    top = occ.addBox(0, -fw / 2, D - tf, L, fw, tf)
    fused, _ = occ.fuse([(3, bottom)], [(3, web), (3, top)])
    r_root = p.get("root_radius", 0.0)
    if r_root > 0:
        # the four web-flange edges: lines along x at y = +-tw/2, z = tf or D - tf
        edges = []
        for _, tag in occ.getEntities(1):
            x0, y0, z0, x1, y1, z1 = occ.getBoundingBox(1, tag)
            if (x1 - x0 > 0.9 * L and abs(abs(y0) - tw / 2) < 1e-6 and abs(y1 - y0) < 1e-6
                    and abs(z1 - z0) < 1e-6 and min(abs(z0 - tf), abs(z0 - (D - tf))) < 1e-6):
                edges.append(tag)
        if len(edges) != 4:
            raise RuntimeError(f"geometry: found {len(edges)} web-flange edges, expected 4")
        fused = occ.fillet([t for _, t in fused], edges, [r_root])
    centres = i_profile_hole_centres(p)
    r = p["bolt_diameter"] / 2
    holes = [(3, occ.addCylinder(x, y, D - 2 * tf, 0, 0, 3 * tf, r)) for x, y in centres]
    occ.cut(fused, holes)
    occ.synchronize()
    hole_tags = _classify_cylinders(gmsh, centres, r, (D - tf, D), 1e-7)
    groups = {"base": _planes_at(gmsh, 2, 0.0, 1e-6), "end_free": _planes_at(gmsh, 2, D, 1e-6)}
    for k, tags in enumerate(hole_tags):
        groups[f"hole_{k}"] = tags
    fillets = [tag for dim, tag in gmsh.model.getEntities(2) if gmsh.model.getType(dim, tag) == "Cylinder"
               and gmsh.model.getBoundingBox(dim, tag)[3] - gmsh.model.getBoundingBox(dim, tag)[0] > 0.9 * L]
    return groups, [t for tags in hole_tags for t in tags] + fillets


_BUILDERS = {"bar": _build_bar, "rail": _build_rail, "joint_plate": _build_joint_plate,
             "i_profile": _build_i_profile}
