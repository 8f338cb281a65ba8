"""The records a check produces, each frozen and built once (SI units throughout):

* :class:`SeedMethod`, :class:`FatigueResult`, :class:`CycleHistory`: the parts of one
  part's cycle result, gathered in :class:`CycleResult`;
* :class:`PartResult`: one part's check (its job, mesh, governing instant and cycle);
* :class:`PipelineResult`: the whole run.

:func:`railcheck.check.summary.summary_of` is the one place that maps them to
``summary.json``'s keys and units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from railcheck.fea.elasticity import Solution
from railcheck.fea.fatigue import Marin
from railcheck.fea.superpose import Envelope, UnitFields
from railcheck.fea.unitcases import UnitSolve
from railcheck.geometry.meshdata import MeshData
from railcheck.kinematics.checks import CheckResult
from railcheck.model.certificate import small_displacement_limit
from railcheck.model.jobs import PartJob
from railcheck.model.kinematics_stage import KinematicsResult
from railcheck.model.utilisation import Limits, criterion_utilisations
from railcheck.scene import Scene
from railcheck.units import floored


@dataclass(frozen=True)
class SeedMethod:
    """Seed 000's single-instant method: the von Mises peak (Pa) over the verdict nodes at
    the instant of the largest reaction magnitude, its crank angle (deg), where (m)."""

    max_von_mises: float
    crank_angle_deg: float
    location: tuple[float, float, float]
    joint: str


@dataclass(frozen=True)
class FatigueResult:
    """The minimum fatigue safety factor over the verdict nodes, where (m), its
    alternating and midrange von Mises stresses (Pa), the endurance limit with its Marin
    factors, the criterion, and ``node_factor`` (nodes,) for the VTU."""

    criterion: str
    marin: Marin
    surface: str
    reliability: float
    min_safety_factor: float
    location: tuple[float, float, float]
    sigma_a: float
    sigma_m: float
    required: float
    node_factor: np.ndarray | None  # None when no node fields are written (no VTU)

    @property
    def passed(self) -> bool:
        return self.min_safety_factor >= self.required


@dataclass(frozen=True)
class CycleHistory:
    """The governing node's von Mises (Pa) at every step (``angles_deg``), the governing
    crank angle, the seed method's step and angle, and the joint that governs."""

    crank_angle_deg: float
    angles_deg: np.ndarray
    von_mises: np.ndarray
    seed_step: int
    joint: str
    seed_angle_deg: float


@dataclass(frozen=True)
class DynamicResult:
    """The dynamic response of one part (effect ``dynamic``): its lowest natural
    frequencies ``hz`` (Hz), the crank harmonic nearest each (``harmonics``, of
    ``crank_hz``), the ``amplification`` (dynamic over quasi-static cycle peak of von
    Mises), both peaks (Pa), the modal ``damping`` ratio used and the largest amplification
    allowed."""

    hz: np.ndarray
    harmonics: np.ndarray
    crank_hz: float
    amplification: float
    quasi_static_peak: float
    dynamic_peak: float
    damping: float
    max_amplification: float

    @property
    def passed(self) -> bool:
        return self.amplification <= self.max_amplification


@dataclass(frozen=True)
class CycleResult:
    """One part over the whole cycle: the envelope, the seed method beside it, fatigue,
    the governing history, the unit fields and the governing source's coefficients ``C``
    (steps, cases), the unit solve's figures, stage seconds and warnings."""

    source: str
    envelope: Envelope
    seed_method: SeedMethod
    fatigue: FatigueResult
    history: CycleHistory
    fields: UnitFields
    C: np.ndarray
    solve: UnitSolve
    dynamic: DynamicResult | None = None

    @property
    def load_C(self) -> np.ndarray:
        """(steps, k) the coefficients of the unit load cases alone (``C`` less the modal
        columns a dynamic response appends)."""
        return self.C[:, : self.solve.resultants.shape[1]]


@dataclass(frozen=True)
class ClampedComparison:
    """A free part checked once more as the 2013 study did, clamped (a rail at its first
    hole, a plate at its seat) with the joint's reaction at its bolts
    (``[check] support = "clamped"``), beside the
    verdict and never part of it: the cycle's von Mises peak away from the clamp's
    singular zone and at the clamp (Pa), the crank angle of the peak (deg), the fatigue
    factor and the free end's largest deflection (m)."""

    max_von_mises: float
    support_peak: float
    crank_angle_deg: float
    fatigue_factor: float
    max_tip: float


@dataclass(frozen=True)
class PartResult:
    """One part's check. ``solution``: the field at the governing instant (for the VTU and
    the picture); ``seconds`` per stage; ``warnings`` about its mesh or loads."""

    job: PartJob
    mesh: MeshData
    solution: Solution
    cycle: CycleResult
    seconds: dict[str, float] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    clamped: ClampedComparison | None = None  # a free rail's 2013 clamped model, for comparison

    @property
    def name(self) -> str:
        return self.job.name

    @property
    def limit(self) -> float:
        """Pa: the stress limit."""
        return self.job.limit

    @property
    def geometry(self):
        return self.job.geometry

    @property
    def load_case(self):
        """The seed method's load case (the factored reaction at its peak instant)."""
        return self.job.load_case

    @property
    def deflection_limit(self) -> float | None:
        """m, from ``[check] max_deflection`` (None: no limit)."""
        return self.job.max_deflection

    @property
    def verdict_stress(self) -> float:
        """Pa: the cycle's peak von Mises away from the support's singular edge (docs/model.md)."""
        return self.cycle.envelope.max_von_mises

    @property
    def stress_passed(self) -> bool:
        return self.verdict_stress <= self.limit

    @property
    def fatigue_passed(self) -> bool:
        return self.cycle.fatigue.passed

    @property
    def deflection_passed(self) -> bool:
        return self.deflection_limit is None or self.cycle.envelope.max_tip <= self.deflection_limit

    @property
    def limits(self) -> Limits:
        """What this part is judged against (:class:`~railcheck.model.utilisation.Limits`)."""
        d = self.cycle.dynamic
        return Limits(
            stress=self.limit,
            fatigue_required=self.cycle.fatigue.required,
            deflection=self.deflection_limit,
            yield_strength=self.job.material.yield_strength,
            length=self.geometry.get("length") or 0.0,
            max_amplification=None if d is None else d.max_amplification,
        )

    @property
    def utilisations(self) -> dict[str, float]:
        """Each criterion's share of its limit (1 = at the limit),
        :func:`~railcheck.model.utilisation.criterion_utilisations` of this part's cycle
        peak, least fatigue factor, largest deflection and (with a dynamic response) its
        amplification: the same function the sweep's rows use."""
        d, env = self.cycle.dynamic, self.cycle.envelope
        amp = None if d is None else d.amplification
        u = criterion_utilisations(self.limits, self.verdict_stress, self.cycle.fatigue.min_safety_factor, env.max_tip, amp)
        return {k: float(v) for k, v in u.items()}

    @property
    def utilisation(self) -> float:
        """The largest of :attr:`utilisations`: the part fails above 1."""
        return max(self.utilisations.values())

    @property
    def governing_criterion(self) -> str:
        """The criterion with the largest utilisation."""
        u = self.utilisations
        return max(u, key=u.__getitem__)

    @property
    def dynamic_passed(self) -> bool:
        """True without a dynamic response, else the amplification within its limit."""
        return self.cycle.dynamic is None or self.cycle.dynamic.passed

    @property
    def within_yield(self) -> bool:
        """True while the linear-elastic peak stays at or below the material's yield
        strength (beyond it the linear result is not physical and the part fails)."""
        return self.utilisations.get("yield", 0.0) <= 1.0

    @property
    def small_displacements(self) -> bool:
        """True while the largest deflection stays within small displacements (beyond them
        the linear result is not valid and the part fails)."""
        return self.utilisations["small-displacement"] <= 1.0

    @property
    def passed(self) -> bool:
        return (
            self.stress_passed
            and self.fatigue_passed
            and self.deflection_passed
            and self.dynamic_passed
            and self.within_yield
            and self.small_displacements
        )


@dataclass(frozen=True)
class PipelineResult:
    """A whole run: the stages that ran (in order), the kinematics, the configuration
    checks, each part's result, the parts left unsolved because nothing loads them,
    the joints' components' checks, warnings and stage timings (s)."""

    scene: Scene
    stages_run: tuple[str, ...] = ()
    kinematics: KinematicsResult | None = None
    kinematics_summary: dict | None = None
    parts: dict[str, PartResult] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    timings: dict[str, float] = field(default_factory=dict)
    checks: dict[str, CheckResult] = field(default_factory=dict)
    unloaded: tuple[str, ...] = ()  # parts with no load at any step: reported, not solved
    components: dict = field(default_factory=dict)  # name -> railcheck.components.ComponentResult
    components_safe_speed: Any = None  # railcheck.check.margins.SafeSpeed: where the components reach 1
    parts_safe_speed: dict = field(default_factory=dict)  # failing part -> SafeSpeed: where it reaches 1
    safe_speed: Any = None  # SafeSpeed up to which every checked part and component passes (None: still crank)

    @property
    def failures(self) -> list[str]:
        """Every reason the run fails: a configuration check or a part's stress, fatigue or
        deflection verdict (empty: pass)."""
        out = [f"check {name}" for name, c in self.checks.items() if not c.ok]
        for name, p in self.parts.items():
            out += [f"{name} stress"] if not p.stress_passed else []
            out += [f"{name} fatigue"] if not p.fatigue_passed else []
            out += [f"{name} deflection"] if not p.deflection_passed else []
            out += [f"{name} dynamic"] if not p.dynamic_passed else []
            out += [f"{name} beyond yield"] if not p.within_yield else []
            out += [f"{name} beyond small displacements"] if not p.small_displacements else []
        for name, c in self.components.items():
            out += [f"{name} {k}" for k, u in c.utilisations.items() if not u <= 1.0]
        return out

    @property
    def failures_with_figures(self) -> list[str]:
        """:attr:`failures` with the figure and the limit of each (MPa, mm), the words an
        engineer acts on: "crank-rail stress 638.8 MPa > 375 MPa"."""
        out = [f"check {name}: {c.message}" for name, c in self.checks.items() if not c.ok]
        for name, p in self.parts.items():
            out += part_failures_with_figures(name, p)
        for name, c in self.components.items():
            out += [f"{name} {k} utilisation {u:.2f} > 1 ({c.standard})" for k, u in c.utilisations.items() if not u <= 1.0]
        return out

    @property
    def to_pass(self) -> list[str]:
        """What would make each failing part and component pass, in words: the share its
        loads must fall to (1 / utilisation: every criterion grows with the loads) and the
        crank speed up to which a failing part passes at this setting, a component's key
        and value that pass (the speed up to which everything passes is
        :func:`safe_speed_words`)."""
        out = []
        for name, p in self.parts.items():
            if p.utilisation > 1.0:
                out.append(
                    f"{name}: its loads down to {1 / p.utilisation:.0%} of these ({p.governing_criterion} "
                    f"utilisation {p.utilisation:.2f}), a lower speed or a stronger material or section"
                )
                safe = self.parts_safe_speed.get(name)
                if safe is not None:
                    out.append(passes_up_to(name, safe))
        for name, c in self.components.items():
            if not c.utilisation <= 1.0:
                out.append(component_fix(name, c))
        return out

    @property
    def passed(self) -> bool:
        return not self.failures


def component_fix(name: str, c) -> str:
    """A failing component's fix in words: the scene key and a value that passes, solved
    from its own criteria (``c.needs``, :mod:`railcheck.components.sizing`), or why none
    that fits does and what would."""
    now = f"{c.governing_criterion} {c.utilisation:.2f}"
    n = c.needs
    if c.kind == "screws" and n.get("screw"):
        size, grade = n["screw"].split()
        return (
            f'{name} ({now}): [components] screw_size = "{size}", screw_class = "{grade}", tightened to '
            f"{n['tightening_torque_Nm']:.1f} N m, passes"
        )
    if c.kind == "screws":
        friction = n.get("friction_needed", math.inf)
        size, grade = (n.get("strongest") or "M6 12.9").split()
        would = (
            f'screw_size = "{size}", screw_class = "{grade}", joint_friction = {math.ceil(friction * 100) / 100:.2f} would'
            if math.isfinite(friction)
            else "no friction would"
        )
        return (
            f"{name} ({now}): no screw the rail's hole admits holds it by friction (it needs "
            f"{n['clamp_needed_N'] / 1e3:.1f} kN clamp per screw); [components] {would}, or carry the load by form "
            "(fitted screws or dowels in reamed holes)"
        )
    if c.kind == "shaft" and "diameter_needed_m" in n:
        mm = math.ceil(n["diameter_needed_m"] * 1e4) / 10
        return f'{name} ({now}): [components] shaft_diameter = "{mm:g} mm" passes (and bearings of that bore)'
    if c.kind == "bearings" and math.isfinite(n.get("spacing_needed_m", math.inf)) and c.governing_criterion == "static":
        mm = math.ceil(n["spacing_needed_m"] * 1e4) / 10
        return f'{name} ({now}): [components] bearing_spacing = "{mm:g} mm" passes'
    if c.kind == "bearings":
        return f"{name} ({now}): a larger bearing (bearing_static, bearing_dynamic) or a lower speed"
    return f"{name} ({now}): a carriage rated {c.utilisation:.2f}x higher (carriage_c0 and its moment ratings)"


def passes_up_to(name: str, safe) -> str:
    """A part's safe speed in words (``safe``: railcheck.check.margins.SafeSpeed)."""
    if not math.isfinite(safe.hz):
        return f"{name}: passes at any speed at this setting (no load on it grows with the speed)"
    if safe.hz > 0:
        return (
            f"{name}: passes up to {floored(safe.hz)} Hz at this setting ({safe.criterion} reaches 1 there): "
            f'[mechanism] speed = "{floored(safe.hz)} Hz"'
        )
    return f"{name}: fails at rest ({safe.criterion}): no speed passes"


def safe_speed_words(safe) -> str:
    """The check's one safe speed in words (``safe``: railcheck.check.margins.SafeSpeed of
    every checked part and component), floored to three figures, never rounded up."""
    sets = f"{safe.component} {safe.criterion}"
    if safe.hz <= 0:
        return f"no speed passes at this setting: {sets} fails at rest"
    if not math.isfinite(safe.hz):
        return "every part and component passes at any speed at this setting (nothing the speed loads reaches its limit)"
    return (
        f"every part and component passes up to {floored(safe.hz)} Hz at this setting ({sets} reaches 1 there; "
        f'dynamics included): [mechanism] speed = "{floored(safe.hz)} Hz" or less'
    )


def apart(value: float, limit: float, decimals: int) -> int:
    """The decimals, from ``decimals`` up to 6, at which ``value`` and ``limit`` first read
    apart: a failure never reads "n 1.00 < 1.00"."""
    d = decimals
    while d < 6 and f"{value:.{d}f}" == f"{limit:.{d}f}":
        d += 1
    return d


def part_failures_with_figures(name: str, p: PartResult) -> list[str]:
    """Each failed criterion of part ``p`` with its figure against its limit."""
    c, fat, yield_strength = p.cycle, p.cycle.fatigue, p.job.material.yield_strength
    out = []
    if not p.stress_passed:
        vm, limit = p.verdict_stress / 1e6, p.limit / 1e6
        d = apart(vm, limit, 1)
        out.append(f"{name} stress {vm:.{d}f} MPa > {limit:.{0 if d == 1 and limit == round(limit) else d}f} MPa")
    if not p.fatigue_passed:
        d = apart(fat.min_safety_factor, fat.required, 2)
        out.append(f"{name} fatigue n {fat.min_safety_factor:.{d}f} < {fat.required:.{d}f}")
    if not p.deflection_passed and p.deflection_limit is not None:
        out.append(f"{name} deflection {c.envelope.max_tip * 1e3:.2f} mm > {p.deflection_limit * 1e3:g} mm")
    if not p.dynamic_passed and c.dynamic is not None:
        out.append(f"{name} dynamic amplification {c.dynamic.amplification:.3f} > {c.dynamic.max_amplification:.2f}")
    if not p.within_yield:
        out.append(f"{name} beyond yield {p.verdict_stress / 1e6:.1f} MPa > sigma_y {yield_strength / 1e6:.0f} MPa")
    if not p.small_displacements:
        limit = small_displacement_limit(p.geometry.get("length"))
        out.append(f"{name} beyond small displacements {c.envelope.max_tip * 1e3:.1f} mm > {limit * 1e3:.1f} mm")
    return out
