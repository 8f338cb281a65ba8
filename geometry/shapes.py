"""The parts' solid models in gmsh's OpenCASCADE kernel: a plain bar, the size-25 rail,
the PF_4b_006 joint plate and the PF_4b_003_v2 I-profile, each returning its named
surface groups and the surfaces the size field refines. Called by the mesher inside a
gmsh session (gmsh is passed in, never imported here). Units m."""

from __future__ import annotations

__all__ = ["BUILDERS", "i_profile_hole_centres"]


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
            if (
                x0 >= cx - radius - tol
                and x1 <= cx + radius + tol
                and y0 >= cy - radius - tol
                and y1 <= cy + radius + tol
                and max(x1 - x0, y1 - y0) > radius
            ):
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
    rg = p.get("groove_radius", 0.0)
    if rg > 0:  # the ball tracks: semicircular grooves along x, two in each side face
        for z in (p["lower_groove_z"], p["upper_groove_z"]):
            for y in (-w / 2, w / 2):
                tools.append((3, occ.addCylinder(-L, y, z, 3 * L, 0, 0, rg)))
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
    grooves = _grooves(gmsh, L, w, rg)
    # a quadratic edge follows an arc of up to about 70 degrees: elements at most the radius
    return groups, refine, ({GROOVE_ELEMENT_PER_RADIUS * rg: grooves} if grooves else {})


def _grooves(gmsh, L, w, radius):
    """Surface tags of the rail's ball-track grooves: cylinders along x in its side faces."""
    if radius <= 0:
        return []
    tags = []
    for dim, tag in gmsh.model.getEntities(2):
        if gmsh.model.getType(dim, tag) != "Cylinder":
            continue
        x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(dim, tag)
        if x1 - x0 > 0.9 * L and min(abs(y0), abs(y1)) > w / 2 - radius - 1e-6:
            tags.append(tag)
    return tags


#: the grooves' largest element edge, in groove radii: a quadratic edge then spans at
#: most about 80 degrees of arc (benchmarks/groove_mesh.py measures what 1.1 and 1.4 cost
#: and give on a prismatic rail in tension)
GROOVE_ELEMENT_PER_RADIUS = 1.4


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
            if (
                x1 - x0 > 0.9 * L
                and abs(abs(y0) - tw / 2) < 1e-6
                and abs(y1 - y0) < 1e-6
                and abs(z1 - z0) < 1e-6
                and min(abs(z0 - tf), abs(z0 - (D - tf))) < 1e-6
            ):
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
    fillets = [
        tag
        for dim, tag in gmsh.model.getEntities(2)
        if gmsh.model.getType(dim, tag) == "Cylinder"
        and gmsh.model.getBoundingBox(dim, tag)[3] - gmsh.model.getBoundingBox(dim, tag)[0] > 0.9 * L
    ]
    return groups, [t for tags in hole_tags for t in tags] + fillets


BUILDERS = {"bar": _build_bar, "rail": _build_rail, "joint_plate": _build_joint_plate, "i_profile": _build_i_profile}
