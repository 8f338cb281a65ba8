"""The cantilever benchmark: a straight steel bar clamped at x = 0 with a tip load,
against Timoshenko beam theory (tip deflection PL^3/(3EI) + PL/(kappa G A), with
Cowper's shear coefficient for a rectangle kappa = 10 (1 + nu) / (12 + 11 nu)) or, in
axial load, PL/(EA)."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar

from .elasticity import HoleLoad, Solution, Support, solve_elasticity
from .materials import MATERIALS, Material

LENGTH, WIDTH, HEIGHT, LOAD = 0.7, 0.023, 0.020, 100.0


def timoshenko_tip(P: float, L: float, width: float, height: float, material: Material, axis: str) -> float:
    """Analytic tip displacement (m) of a rectangular cantilever: ``axis`` "z" bends
    about y (load along z, depth = height), "y" about z (load along y, depth = width),
    "x" is axial."""
    E, nu = material.youngs_modulus, material.poisson_ratio
    G = E / (2 * (1 + nu))
    A = width * height
    if axis == "x":
        return P * L / (E * A)
    depth, breadth = (height, width) if axis == "z" else (width, height)
    inertia = breadth * depth**3 / 12.0
    kappa = 10 * (1 + nu) / (12 + 11 * nu)
    return P * L**3 / (3 * E * inertia) + P * L / (kappa * G * A)


@dataclass
class CantileverResult:
    solution: Solution
    analytic: float
    computed: float
    seconds: dict[str, float]

    @property
    def relative_error(self) -> float:
        return (self.computed - self.analytic) / self.analytic


def run_cantilever(
    order: int = 2,
    size: float = 4e-3,
    axis: str = "z",
    solver: str = "auto",
    length: float = LENGTH,
    width: float = WIDTH,
    height: float = HEIGHT,
    load: float = LOAD,
    material: Material = MATERIALS["steel"],
    cache: bool = True,
) -> CantileverResult:
    """Mesh, solve and compare; ``size`` in m."""

    t = time.perf_counter()
    mesh = mesh_part(bar(length, width, height), size, hole_size=size, cache=cache)
    mesh_seconds = mesh.seconds if not mesh.cached else time.perf_counter() - t
    direction = {"x": 0, "y": 1, "z": 2}[axis]
    force = np.zeros(3)
    force[direction] = load
    sol = solve_elasticity(
        mesh,
        material,
        [Support("clamp")],
        [HoleLoad("tip", (float(force[0]), float(force[1]), float(force[2])))],
        order=order,
        tip_group="tip",
        solver=solver,
    )
    seconds = {"mesh": mesh_seconds, **sol.seconds}
    return CantileverResult(
        sol, timoshenko_tip(load, length, width, height, material, axis), float(sol.tip_displacement[direction]), seconds
    )
