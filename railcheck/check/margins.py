"""What would make a check pass: the crank speed up to which the joints' components, and
each failing part, pass at the check's setting.

The components' model is analytic (kinematics and standards' formulas, milliseconds a
speed), so their speed is searched exactly on the check's own model: its kinematics rerun
at each trial speed, the same components checked, the largest utilisation's crossing of 1
found by :func:`railcheck.model.crossing.increasing_crossing` (every utilisation grows with
the speed: the joint forces and torque are the inertia's, growing with its square, over
constant weight).

A failing part's speed is searched the same way on the part's own model: at each trial
speed the check's kinematics, loads and job are rebuilt for that part alone and its cycle
evaluated on the unit fields it already solved (superposition: nothing is assembled or
solved again, about a second a trial), its utilisation the check's own
(:attr:`~railcheck.model.records.PartResult.utilisations`) together with the quasi-static
certificate's share (:func:`railcheck.model.utilisation.quasi_static_share`: above its
tolerance the quasi-static verdict no longer holds, so the speed stops there too, as in
``railcheck sweep``)."""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from railcheck.components.scene_checks import ComponentsInput, check_listed_components
from railcheck.model.certificate import QUASI_STATIC_TOLERANCE, certificate
from railcheck.model.crossing import increasing_crossing, refine_crossing
from railcheck.model.cycle import evaluate_cycle
from railcheck.model.inputs import PartsInput
from railcheck.model.jobs import build_load_cases, part_jobs
from railcheck.model.kinematics_stage import KinematicsInput, run_kinematics
from railcheck.model.loading import unit_cases
from railcheck.model.records import PartResult, passes_up_to
from railcheck.units import floored


@dataclasses.dataclass(frozen=True)
class SafeSpeed:
    """The crank speed (Hz) up to which every listed component passes at the check's
    setting (0: one fails at rest; inf: none reaches its limit at any speed), and the
    component and criterion that reach their limit there."""

    hz: float
    component: str
    criterion: str


#: the speed ratio squared a part's search takes for rest: the inertia's share of the
#: check's 1e-6 (the crank at 1/1000 of its speed), its utilisation the weight's to about
#: 1e-7 of the inertia's; at 1e-12 the inertia's columns sit at round-off and defeat the
#: fatigue screening (about 30 s a trial on a rail against 2)
RESTING = 1e-6

#: refinement steps of a failing part's safe speed (each a cycle evaluation, about a second)
PART_SEARCH_STEPS = 12

#: trial speeds, evenly spaced up to the limiting one, at which a part with an exact dynamic
#: response is evaluated (its utilisation need not grow with the speed: a harmonic meets a
#: mode); the sweep scans the same number (railcheck.sweep.verdicts.SAFE_SPEED_SCAN)
DYNAMIC_SCAN = 8


def components_at_speed(kinematics: KinematicsInput, components: ComponentsInput, speed: float) -> dict:
    """name -> ComponentResult of the listed ``components`` with the crank at ``speed``
    rad/s: the kinematics rerun at that speed, the components checked on its joint histories."""
    return check_listed_components(components, run_kinematics(kinematics.at_speed(speed)))


def _largest(results: dict) -> tuple[float, str, str]:
    name = max(results, key=lambda n: float(results[n].utilisation))
    return float(results[name].utilisation), name, str(results[name].governing_criterion)


def components_safe_speed(kinematics: KinematicsInput, components: ComponentsInput) -> SafeSpeed | None:
    """The crank speed up to which the listed ``components`` pass (None without components
    or without a speed to scale: a static scene)."""
    if not components.listed or kinematics.mechanism.speed <= 0:
        return None
    base = kinematics.mechanism.speed

    def u_of(s, idx):
        return np.array([_largest(components_at_speed(kinematics, components, base * math.sqrt(si)))[0] for si in s])

    s = float(increasing_crossing(u_of, 1)[0])
    hz = base * math.sqrt(s) / (2 * math.pi)
    _, name, criterion = _largest(
        components_at_speed(kinematics, components, base * math.sqrt(s) if math.isfinite(s) else base)
    )
    return SafeSpeed(hz, name, criterion)


def part_at_speed(parts: PartsInput, kinematics: KinematicsInput, part: PartResult, speed: float) -> tuple[float, str]:
    """(utilisation, governing criterion) of the checked ``part`` with the crank at
    ``speed`` rad/s: its job rebuilt at that speed, its cycle evaluated on its solved unit
    fields, the certificate's quasi-static share beside the check's criteria (module doc)."""
    inputs = parts.at_speed(speed).only((part.name,))
    kin = run_kinematics(kinematics.at_speed(speed))
    geometries = {part.name: part.job.geometry}
    cases = build_load_cases(inputs, kin, geometries)
    job = part_jobs(inputs, kin, geometries, cases, part.job.material, part.limit)[part.name]
    if not any(np.any(h.C) for h in job.histories):  # at rest without gravity: nothing loads it
        return 0.0, "stress"
    if part.cycle.solve.modes is not None and part.job.dynamic is not None:  # the check's exact response, at this speed
        job = dataclasses.replace(job, dynamic=dataclasses.replace(part.job.dynamic, speed=speed))
    cycle = evaluate_cycle(job, part.cycle.fields, job.histories, part.cycle.solve)
    u = dataclasses.replace(part, job=job, cycle=cycle).utilisations
    base = part.job.certificate
    if base is not None and part.cycle.solve.modes is None and speed > 0:  # the quasi-static verdict's range
        names = list(unit_cases(job.loads, job.geometry, list(job.holes)))
        cert = certificate([h.C for h in job.histories], names, speed, base.lowest_hz, base.source, parts.dynamic.damping)
        u["quasi-static"] = max((cert.estimate - 1.0) / (QUASI_STATIC_TOLERANCE - 1.0), 0.0) if not cert.holds else 0.0
    name = max(u, key=u.__getitem__)
    return float(u[name]), name


def part_safe_speed(parts: PartsInput, kinematics: KinematicsInput, part: PartResult) -> SafeSpeed | None:
    """The crank speed up to which ``part`` passes at the check's setting (module doc);
    None for a part the speed does not load (explicit loads) or a still crank."""
    if part.name in parts.check.loads or parts.mechanism is None or parts.mechanism.speed <= 0:
        return None
    base, seen = parts.mechanism.speed, {}

    def at(s: float) -> tuple[float, str]:
        if s not in seen:  # "at rest" a crank speed 1e-6 of the check's: the same unit cases (inertia's included)
            seen[s] = part_at_speed(parts, kinematics, part, base * math.sqrt(max(s, RESTING)))
        return seen[s]

    at.seen = seen  # type: ignore[attr-defined]
    s = float(increasing_crossing(lambda ss, idx: np.array([at(float(x))[0] for x in ss]), 1, PART_SEARCH_STEPS)[0])
    criterion = at(s)[1] if math.isfinite(s) else part.governing_criterion
    s = passing_side(at, s) if math.isfinite(s) and s > 0 else s
    return SafeSpeed(base * math.sqrt(s) / (2 * math.pi), part.name, criterion)


def failing_parts_safe_speeds(
    inputs: PartsInput, kinematics: KinematicsInput, parts: dict, progress
) -> dict[str, SafeSpeed]:
    """name -> :class:`SafeSpeed` of every part (``parts``: name -> PartResult) that fails
    its criteria at a turning crank."""
    out = {}
    for name, part in parts.items():
        if part.utilisation > 1.0 and name not in inputs.check.loads and inputs.mechanism is not None:
            t = time.perf_counter()
            progress.say("margins", f"{name}: the crank speed at which it passes (its cycle at trial speeds)")
            safe = part_safe_speed(inputs, kinematics, part)
            if safe is not None:
                out[name] = safe
                progress.say("margins", f"{passes_up_to(name, safe)} ({time.perf_counter() - t:.1f} s)")
    return out


def safe_speed(
    inputs: PartsInput, kinematics: KinematicsInput, parts: dict, components: SafeSpeed | None, failing: dict, progress
) -> SafeSpeed | None:
    """The crank speed (Hz) up to which every checked part and component passes at the
    check's setting and what reaches its limit there: the least of the components' safe
    speed ``components``, the failing parts' ``failing`` (name -> SafeSpeed) and each
    passing part's own crossing, found only where it lies below that least speed (a
    passing part is evaluated there and searched only if it fails: module doc). None for a
    still crank or when nothing is checked that the speed moves."""
    if inputs.mechanism is None or inputs.mechanism.speed <= 0:
        return None
    known = [v for v in (components, *failing.values()) if v is not None]
    least = min(known, key=lambda v: v.hz, default=None)
    passing = [p for n, p in parts.items() if n not in failing and n not in inputs.check.loads]
    start = time.perf_counter()
    for part in sorted(passing, key=lambda p: p.utilisation, reverse=True):  # likeliest to limit first
        limit = f"{floored(least.hz)} Hz" if least is not None and 0 < least.hz < math.inf else "its own limit"
        progress.say("margins", f"{part.name}: does it pass from rest up to {limit}? (its cycle at trial speeds)")
        found = passing_part_crossing(inputs, kinematics, part, least.hz if least is not None else math.inf)
        if found is not None:
            least = found
            progress.say("margins", passes_up_to(part.name, found))
    if passing:
        progress.say("margins", f"{len(passing)} passing part(s) searched in {time.perf_counter() - start:.1f} s")
    return least


def passing_part_crossing(
    parts: PartsInput, kinematics: KinematicsInput, part: PartResult, cap_hz: float
) -> SafeSpeed | None:
    """Where the passing ``part`` first reaches 1 below ``cap_hz`` (Hz), or None if it
    passes up to there. Quasi-static its criteria are convex in the speed ratio squared
    (a von Mises peak of loads affine in it, Goodman's parts), so passing at rest and at the
    check's speed means passing between them, and beyond the check's speed passing at the
    cap too means passing up to it: one or two trials. An exact dynamic response is
    scanned at :data:`DYNAMIC_SCAN` speeds up to the cap. Without a cap its own safe speed
    (:func:`part_safe_speed`)."""
    if not math.isfinite(cap_hz):
        return part_safe_speed(parts, kinematics, part)
    base = parts.linkage_spec.speed
    cap = (2 * math.pi * cap_hz / base) ** 2
    if part.cycle.solve.modes is not None:
        trials = np.linspace(0.0, math.sqrt(cap), DYNAMIC_SCAN + 1) ** 2
    else:
        trials = np.array([0.0, cap] if cap > 1.0 else [0.0])
    seen = {1.0: (part.utilisation, part.governing_criterion)}

    def at(s: float) -> tuple[float, str]:
        if s not in seen:
            seen[s] = part_at_speed(parts, kinematics, part, base * math.sqrt(max(s, RESTING)))
        return seen[s]

    at.seen = seen  # type: ignore[attr-defined]
    points = sorted({float(x) for x in trials} | {1.0})
    for k, s in enumerate(points):
        if at(s)[0] > 1.0:
            return SafeSpeed(0.0, part.name, at(s)[1]) if k == 0 else _refined(part.name, at, points[k - 1], s, base)
    return None


def _refined(name: str, at, below: float, above: float, base: float) -> SafeSpeed:
    """The crossing between the speed ratios squared ``below`` (passing) and ``above``
    (failing) of the memoised ``at(s) -> (utilisation, criterion)`` (:func:`refine_crossing`
    from the two ends and one point already evaluated, rest or the check's own speed), as a
    SafeSpeed whose criterion is the one failing at ``above``."""

    def u_of(x, idx):
        return np.array([at(float(v))[0] for v in x])

    third = 0.0 if below > 0.0 else 1.0
    lower, upper, off = ((np.array([x]), u_of([x], None)) for x in (below, above, third))
    s = float(refine_crossing(u_of, lower, upper, off, np.array([True]), PART_SEARCH_STEPS)[0])
    return SafeSpeed(base * math.sqrt(passing_side(at, s)) / (2 * math.pi), name, at(above)[1])


def passing_side(at, s: float) -> float:
    """``s`` if ``at(s)`` passes, else a passing point just below it: a search returns the
    bracket's end nearer 1, which may be the failing one (its other end far below when the
    iterates approach from above). Secant steps from the largest passing trial below to the
    failing end land at or below the crossing where the utilisation is convex in ``s`` (the
    chord lies above the curve), each at least 1e-12 below the failing end (an excess at
    round-off); after three that fail, that passing trial itself. A safe speed is never
    above a failing trial."""
    u = at(s)[0]
    if u <= 1.0:
        return s
    a = max((x for x, (ux, _) in at.seen.items() if x < s and ux <= 1.0), default=None)
    if a is None:
        return 0.0
    ua = at(a)[0]
    for _ in range(3):
        x = min(a + (1.0 - ua) * (s - a) / (u - ua), s * (1.0 - 1e-12))
        if not a < x:
            break
        if at(x)[0] <= 1.0:
            return x
        s, u = x, at(x)[0]
    return a
