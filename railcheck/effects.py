"""The effects a scene calls for, defined once: which loads a run simulates and whether
it computes the dynamic response, from the effects a scene lists and the crank speeds
(rad/s) it runs at. The check (one speed) and the sweep (its speeds) both ask here.
"""

from __future__ import annotations

from collections.abc import Iterable

EFFECTS = ("inertia", "gravity", "rail-inertia", "dynamic")


def simulated_effects(requested: tuple[str, ...], speeds: Iterable[float]) -> tuple[str, ...]:
    """The loads simulated from the effects ``requested`` at the crank ``speeds`` (rad/s):
    "inertia" only when listed and some speed is not zero (a still rig has none), "gravity"
    when listed. The one definition the check and the sweep use."""
    inertia = "inertia" in requested and any(w > 0 for w in speeds)
    return (("inertia",) if inertia else ()) + (("gravity",) if "gravity" in requested else ())


def rig_plane(mechanism_plane: str | None, requested: tuple[str, ...]) -> str:
    """The plane the rig moves in, which decides where its weight acts: [mechanism]'s
    ``mechanism_plane``, or without a mechanism "vertical" when "gravity" is ``requested``
    (the weight in the plane of the loads), else "horizontal"."""
    if mechanism_plane is not None:
        return mechanism_plane
    return "vertical" if "gravity" in requested else "horizontal"


def dynamic_response(requested: tuple[str, ...], speeds: Iterable[float]) -> bool:
    """Whether the dynamic response is computed: "dynamic" listed and some crank speed
    (rad/s) not zero (a still rig has no cycle to respond to)."""
    return "dynamic" in requested and any(w > 0 for w in speeds)
