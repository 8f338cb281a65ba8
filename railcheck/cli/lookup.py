"""``railcheck lookup 480/840/780/1020``: one setting's card for the lab, from a sweep's
table when it holds the setting, else from a check of the built-in scene at that setting
(:mod:`railcheck.sweep.lookup`)."""

from __future__ import annotations

import math
import textwrap
import time
from pathlib import Path

import railcheck.api as api
from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.files import to_json
from railcheck.ranges import in_range
from railcheck.scene import load_scene
from railcheck.sweep.lookup import Card, card_from_check, cards_from_table, parse_setting, table_path
from railcheck.units import floored, parse_quantity

HELP = "one setting's card: verdict, safe speed and what sets it, motor, every utilisation"
PARSER = {
    "description": "One setting of the rig, as a teacher asks it: is it safe, up to what speed, what "
    "sets that, what does the motor give. Read from a sweep's table when it holds the setting "
    "(--sweep DIR, default sweep/), else a check of the built-in scene at that setting (a minute or two).",
    "epilog": "exit status: 0 the setting passes at every speed shown, 1 it fails at one, 2 bad input",
}


def add_args(p) -> None:
    p.add_argument("setting", help="bar lengths in mm: crank/coupler/rocker/ground, or crank/coupler/offset")
    p.add_argument("--sweep", metavar="DIR", default="sweep", help="a sweep's results folder (default: sweep)")
    p.add_argument("--speed", metavar="HZ", help='the crank speed, e.g. "0.8 Hz" (default: the table\'s speeds or 1 Hz)')
    p.add_argument("--json", action="store_true", help="print the cards as JSON")


def run(args) -> int:
    t0 = time.perf_counter()
    kind, lengths = parse_setting(args.setting)
    speed = (
        in_range(parse_quantity(args.speed, "angular_speed", "--speed", positive=True, allow_zero=False), "speed", "--speed")
        if args.speed
        else None
    )
    hz = speed / (2 * math.pi) if speed is not None else None
    path = table_path(Path(args.sweep), kind)
    cards = cards_from_table(path, kind, lengths, hz) if path is not None else []
    if not cards:
        cards = [_checked(kind, lengths, hz)]
    seconds = time.perf_counter() - t0
    if args.json:
        print(to_json({"cards": [card.__dict__ for card in cards], "seconds": seconds}))
    else:
        print("\n\n".join(card_words(card) for card in cards))
        print(f"answered from {cards[0].source} in {seconds:.2f} s")
    return EXIT_PASS if all(c.verdict == "PASS" for c in cards) else EXIT_FAIL


def _checked(kind: str, lengths: dict, hz: float | None) -> Card:
    """The card of a check of the built-in scene at this setting (four-bar only)."""
    if kind != "four-bar":
        raise InputError("setting", "a slider-crank setting is looked up in a sweep's table only (--sweep DIR)")
    raw = load_scene(None).raw
    mechanism = raw["mechanism"] | {bar: f"{v * 1e3:g} mm" for bar, v in lengths.items()}
    if hz is not None:
        mechanism["speed"] = f"{hz!r} Hz"
    run = api.check({**raw, "mechanism": mechanism}, progress=True)
    return card_from_check(run.result, run.summary, kind, lengths)


def card_words(card: Card) -> str:
    """The card in an engineer's words: mm, Hz, N m, W; the safe speed floored."""
    setting = "/".join(f"{v * 1e3:g}" for v in card.lengths_m.values())
    if card.safe_speed_hz != card.safe_speed_hz and card.reason:  # NaN: a configuration check fails
        safe = f"not evaluated further: a configuration check fails ({card.reason}); no speed is safe"
    elif card.safe_speed_hz != card.safe_speed_hz:
        safe = "no speed limit computed (no turning crank)"
    elif math.isinf(card.safe_speed_hz):
        safe = "safe at any speed (nothing the speed loads reaches its limit)"
    elif card.safe_speed_hz <= 0:
        safe = f"fails at rest: {card.safe_set_by} {card.safe_criterion} (no speed passes)"
    else:
        safe = f"safe up to {floored(card.safe_speed_hz)} Hz ({card.safe_set_by} {card.safe_criterion} sets it)"
    worst = sorted(card.utilisations.items(), key=lambda kv: -kv[1])
    uses = textwrap.fill(
        "utilisation (share of each limit): " + (", ".join(f"{name} {u:.0%}" for name, u in worst) or "none computed"),
        98,
        initial_indent="  ",
        subsequent_indent="    ",
    )
    lines = [
        f"{card.kind} {setting} mm at {card.speed_hz:g} Hz: {card.verdict}" + (f" ({card.reason})" if card.reason else ""),
        f"  {safe}",
        f"  motor: peak torque {card.torque_peak_Nm:.1f} N m, peak power {card.power_peak_W:.0f} W at {card.speed_hz:g} Hz",
        uses,
    ]
    return "\n".join(lines)
