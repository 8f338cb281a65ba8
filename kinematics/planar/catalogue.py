"""The mechanisms of seed 002 (and the rig's linkages) in body coordinates.

Dimensions come from seed 002's ``DatosE`` and initial coordinates from its ``Coor``
vectors; body and point numbering follow the seed: piece N is body N - 1 here, point
"pK" is its point NK. Seed 002 gives no unit: its numbers are read as millimetres and
converted to metres here. Joints follow its ``Revolute2``/``Translate2`` lists: for
``Translate2[Line[a, p, q], Line[b, r, s]]``, point p of piece a lies on the line r-s of
piece b, and the lines are parallel (as its printed constraint equations show).

Frames: each mechanism's ground frame is the one of the curve equation Artobolevsky gives
(O and Ox for the strophoid a-z-1139; the midpoint O of AC and the line AC for the
hyperbola a-z-1066), so the tracer point's coordinates are in the catalogue's frame.

Guides: seed 002 lengthened the guides of pieces 5 and 6 of a-z-1139 (and the arm of
piece 8 of a-z-1066 is 40 long) so the curve can be completed; here every prismatic
joint acts along an unbounded line, which is the same as lengthening every guide.
"""

from __future__ import annotations

import math

import numpy as np

from ..linkage import FourBar, SliderCrank
from ..massmodel import MassModel, fourbar_bodies, slidercrank_bodies
from ..motion import solve_fourbar, solve_slidercrank
from .model import Body, Mechanism, Prismatic, Revolute, RotationDriver

MM = 1e-3


def _scale(points: dict, k: float = MM) -> dict:
    return {name: (x * k, y * k) for name, (x, y) in points.items()}


def _body(name, points, x, y, deg, mass=0.0, inertia=0.0):
    return Body(name, _scale(points), mass, inertia, (x * MM, y * MM, math.radians(deg)))


def _translate2(name, a, p, q, b, r, s):
    """Mechanica's Translate2[Line[a, p, q], Line[b, r, s]] (pieces a, b; 0-based bodies)."""
    return Prismatic(name, b, r, s, a, p, q)


def linear_driver(start_deg: float, sweep_deg: float):
    """theta = start + s for s in [0, sweep] (rad): f(s) = (value, 1, 0)."""
    start = math.radians(start_deg)
    return lambda s: (start + s, 1.0, 0.0)


def a_4_1553() -> Mechanism:
    """a-4-1553: crank (piece 2), L-shaped coupler (piece 3) carrying the tracer, slider
    (piece 4) on the ground's horizontal guide y = L11. Seed 002, 2.4.2 and 2.5.2.
    The tracer point 35's position on the L-shaped piece is in a picture only: assumed
    at (-L31 + L33, L32)."""
    L11, L12, L13, L14 = 6.0, 3.6, 4.0, 40.0
    L2, L31, L32, L33, L4 = 12.5, 9.75, 10.0, 3.0, 3.0
    ground = Body("1", _scale({"p1": (0, 0), "p2": (0, L11), "p3": (-L13, -L12), "p4": (L14, L11)}))
    bodies = [
        _body("2", {"p1": (0, 0), "p2": (L2, 0), "p3": (-L2, 0)}, 7.60, -8.25, 338.17),
        _body(
            "3",
            {"p1": (0, 0), "p2": (L31, 0), "p3": (-L31, 0), "p4": (-L31, L32), "p5": (-L31 + L33, L32)},
            21.62,
            -3.45,
            75.69,
        ),
        _body("4", {"p1": (0, 0), "p2": (L4, 0)}, 24.03, 6.0, 0.0),
    ]
    joints = [
        Revolute("1", 0, "p3", 1, "p3"),
        Revolute("2", 1, "p2", 2, "p3"),
        Revolute("3", 2, "p2", 3, "p1"),
        _translate2("4", 0, "p2", "p4", 3, "p1", "p2"),
    ]
    return Mechanism(
        "a-4-1553",
        ground,
        bodies,
        joints,
        (RotationDriver("driver", 1, linear_driver(338.17, 225.0)),),
        tracer=(2, "p5"),
        description="Artobolevsky a-4-1553 (the mechanisms study): crank, L-shaped coupler, slider",
    )


def a_z_1139() -> Mechanism:
    """a-z-1139, strophoid OD = a cos(2 phi) / cos(phi), OA = AC = a (= 2 L2 = 2 L41).
    Seed 002, 2.4.3 (Coor, DatosE, joints) and 2.5.3 (its 21 constraint equations)."""
    L11, L12, L2, L3 = 40.0, 10.0, 15.0, 3.0
    L41, L42, L51, L52, L61, L7, L8 = 15.0, 3.0, 30.0, 3.0, 32.5, 3.0, 3.0
    ground = Body("1", _scale({"p1": (0, 0), "p2": (-L11, 0), "p3": (L12, 0)}))
    bodies = [
        _body("2", {"p1": (0, 0), "p2": (L2, 0), "p3": (-L2, 0)}, -5.30, 14.03, 110.71),
        _body("3", {"p1": (0, 0), "p2": (L3, 0)}, -10.61, -15.35, 90.0),
        _body("4", {"p1": (0, 0), "p2": (L41, 0), "p3": (-L41, 0), "p4": (-L41, L42)}, 4.39, 28.06, 0.0),
        _body("5", {"p1": (0, 0), "p2": (L51, 0), "p3": (-L51, 0), "p5": (0, L52)}, -10.61, 0.0, 90.0),
        _body("6", {"p1": (0, 0), "p2": (L61, 0), "p3": (-L61, 0)}, 18.48, 26.74, 55.35),
        _body("7", {"p1": (0, 0), "p2": (L7, 0)}, 19.39, 28.06, 55.35),
        _body("8", {"p1": (0, 0), "p2": (L8, 0)}, -10.61, -15.35, 55.35),
    ]
    joints = [
        Revolute("1", 0, "p1", 1, "p3"),
        Revolute("2", 1, "p2", 3, "p3"),
        _translate2("3", 4, "p2", "p3", 3, "p3", "p4"),
        _translate2("4", 0, "p1", "p3", 4, "p1", "p5"),
        Revolute("5", 0, "p1", 5, "p3"),
        _translate2("6", 5, "p1", "p2", 6, "p1", "p2"),
        _translate2("7", 5, "p3", "p2", 7, "p1", "p2"),
        Revolute("8", 2, "p1", 7, "p1"),
        _translate2("9", 2, "p2", "p1", 4, "p3", "p1"),
        Revolute("10", 3, "p2", 6, "p1"),
    ]
    mech = Mechanism(
        "a-z-1139",
        ground,
        bodies,
        joints,
        (RotationDriver("driver", 1, linear_driver(110.71, -220.0)),),
        tracer=(7, "p1"),
        description="Artobolevsky a-z-1139 (the mechanisms study): strophoid tracer",
    )
    mech.curve_parameters = {"a": 2 * L2 * MM}
    return mech


def a_z_1066() -> Mechanism:
    """a-z-1066, hyperbolograph of Inwards: rhombus EBCD, a = AO = OC, 2l = AE.
    Seed 002, 2.4.4 (Coor, DatosE, its 13 joints); driver: piece 8 about A."""
    a, L2, L3, L4, L81, L82, L9, L10 = 20.0, 3.0, 3.0, 12.5, 12.5, 40.0, 35.0, 3.0
    ground = Body("1", _scale({"p1": (0, 0), "p2": (a, 0), "p3": (-a, 0)}))
    bar = {"p1": (0, 0), "p2": (L4, 0), "p3": (-L4, 0)}
    bodies = [
        _body("2", {"p1": (0, 0), "p2": (L2, 0), "p3": (-L2, 0)}, 16.88, 14.17, 21.02),
        _body("3", {"p1": (0, 0), "p2": (L3, 0), "p3": (-L3, 0)}, 16.88, 14.17, 61.71),
        _body("4", bar, 21.32, 12.43, 263.95),
        _body("5", bar, 10.35, -7.95, 39.47),
        _body("6", bar, 12.99, 16.91, 39.47),
        _body("7", bar, 2.02, -3.46, 263.95),
        _body("8", {"p1": (0, 0), "p2": (L81, 0), "p3": (-L81, 0), "p4": (L82, 0)}, -8.33, 4.48, 21.02),
        _body("9", {"p1": (0, 0), "p2": (L9, 0), "p3": (-L9, 0)}, 6.05, -5.96, 61.71),
        _body("10", {"p1": (0, 0), "p2": (L10, 0)}, 0.70, -15.89, 61.71),
    ]
    joints = [
        Revolute("1", 0, "p2", 3, "p2"),
        Revolute("2", 0, "p2", 4, "p2"),
        Revolute("3", 5, "p3", 7, "p2"),
        Revolute("4", 6, "p3", 7, "p2"),
        Revolute("5", 0, "p3", 7, "p3"),
        Revolute("6", 3, "p3", 8, "p2"),
        Revolute("7", 5, "p2", 8, "p2"),
        _translate2("8", 8, "p3", "p1", 9, "p1", "p2"),
        Revolute("9", 4, "p3", 9, "p1"),
        Revolute("10", 6, "p2", 9, "p1"),
        Revolute("11", 1, "p1", 2, "p1"),
        _translate2("12", 1, "p3", "p2", 7, "p2", "p4"),
        _translate2("13", 2, "p3", "p2", 8, "p2", "p1"),
    ]
    mech = Mechanism(
        "a-z-1066",
        ground,
        bodies,
        joints,
        (RotationDriver("driver", 7, linear_driver(21.02, -40.0)),),
        tracer=(1, "p1"),
        description="Artobolevsky a-z-1066 (the mechanisms study): hyperbolograph of Inwards",
    )
    mech.curve_parameters = {"a": a * MM, "l": L81 * MM}
    return mech


def rig_fourbar(linkage: FourBar = FourBar(0.48, 0.84, 0.78, 1.02), masses: MassModel = MassModel()) -> Mechanism:
    """The rig's four-bar (seed 000) in body coordinates; each body's origin is its
    centre of mass (kinematics.massmodel), its x axis along the bar."""

    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    crank, coupler, rocker = fourbar_bodies(linkage, masses)
    m0 = solve_fourbar(linkage, 0.0, 3)
    th = m0.theta[0]

    def place(origin, angle, com):
        return (origin[0] + com * math.cos(angle), origin[1] + com * math.sin(angle), angle)

    ground = Body("ground", {"O2": (0.0, 0.0), "O4": (d, 0.0)})
    bodies = [
        Body(
            "crank",
            {"O2": (-crank.com, 0.0), "A": (b2 - crank.com, 0.0)},
            crank.mass,
            crank.inertia_com,
            place((0.0, 0.0), th[0], crank.com),
        ),
        Body(
            "coupler",
            {"A": (-coupler.com, 0.0), "P": (0.5 * b3 - coupler.com, 0.0), "B": (b3 - coupler.com, 0.0)},
            coupler.mass,
            coupler.inertia_com,
            place(m0.points["A"][0], th[1], coupler.com),
        ),
        Body(
            "rocker",
            {"O4": (-rocker.com, 0.0), "B": (b4 - rocker.com, 0.0)},
            rocker.mass,
            rocker.inertia_com,
            place((d, 0.0), th[2], rocker.com),
        ),
    ]
    joints = [
        Revolute("O2", 0, "O2", 1, "O2"),
        Revolute("A", 1, "A", 2, "A"),
        Revolute("B", 2, "B", 3, "B"),
        Revolute("O4", 0, "O4", 3, "O4"),
    ]
    return Mechanism(
        "rig-four-bar",
        ground,
        bodies,
        joints,
        (RotationDriver("driver", 1, linear_driver(0.0, 360.0)),),
        tracer=(2, "P"),
        description="the rig's four-bar (the 2013 study) in body coordinates; P: the coupler's mid-span, a coupler point",
    )


def rig_slidercrank(linkage: SliderCrank = SliderCrank(0.48, 0.84, 0.0), masses: MassModel = MassModel()) -> Mechanism:
    """The rig's slider-crank in body coordinates (slider: a particle on the line y = offset)."""

    b2, b3, e = linkage.crank, linkage.coupler, linkage.offset
    crank, coupler, slider = slidercrank_bodies(linkage, masses)
    m0 = solve_slidercrank(linkage, 0.0, 3)
    th = m0.theta[0]
    A0, B0 = m0.points["A"][0], m0.points["B"][0]
    ground = Body("ground", {"O2": (0.0, 0.0), "L1": (0.0, e), "L2": (1.0, e)})
    bodies = [
        Body(
            "crank",
            {"O2": (-crank.com, 0.0), "A": (b2 - crank.com, 0.0)},
            crank.mass,
            crank.inertia_com,
            (crank.com * math.cos(th[0]), crank.com * math.sin(th[0]), th[0]),
        ),
        Body(
            "coupler",
            {"A": (-coupler.com, 0.0), "B": (b3 - coupler.com, 0.0)},
            coupler.mass,
            coupler.inertia_com,
            (A0[0] + coupler.com * math.cos(th[1]), A0[1] + coupler.com * math.sin(th[1]), th[1]),
        ),
        Body("slider", {"B": (0.0, 0.0), "ahead": (1.0, 0.0)}, slider.mass, 0.0, (B0[0], B0[1], 0.0)),
    ]
    joints = [
        Revolute("O2", 0, "O2", 1, "O2"),
        Revolute("A", 1, "A", 2, "A"),
        Revolute("B", 2, "B", 3, "B"),
        Prismatic("slider", 0, "L1", "L2", 3, "B", "ahead"),
    ]
    return Mechanism(
        "rig-slider-crank",
        ground,
        bodies,
        joints,
        (RotationDriver("driver", 1, linear_driver(0.0, 360.0)),),
        tracer=(3, "B"),
        description="the rig's slider-crank in body coordinates",
    )


CATALOGUE = {
    "a-4-1553": a_4_1553,
    "a-z-1139": a_z_1139,
    "a-z-1066": a_z_1066,
    "four-bar": rig_fourbar,
    "slider-crank": rig_slidercrank,
}

#: the driver's sweep (rad) of each catalogue mechanism, from seed 002's angular speeds x 1 s
SWEEPS = {
    "a-4-1553": math.radians(225.0),
    "a-z-1139": math.radians(-220.0),
    "a-z-1066": math.radians(-40.0),
    "four-bar": 2 * math.pi,
    "slider-crank": 2 * math.pi,
}


def driver_values(name: str, steps: int) -> np.ndarray:
    """The driver parameter s over the mechanism's traced range (rad)."""
    return np.linspace(0.0, SWEEPS[name], int(steps))
