"""Long blocking work is never silent: the heartbeat reports elapsed time while it runs."""

import time

from railcheck.fea.progress import heartbeat


def test_heartbeat_reports_while_the_work_runs_and_when_it_ends():
    lines = []
    with heartbeat("factorising 1000 DOFs", lines.append, interval=0.05):
        time.sleep(0.32)
    assert lines[0] == "factorising 1000 DOFs"
    ticks = [ln for ln in lines if ln.endswith(" s") and "..." in ln]
    assert len(ticks) >= 4  # one every interval
    assert lines[-1].startswith("factorising 1000 DOFs: done in 0.3")


def test_heartbeat_is_silent_without_a_reporter(capsys):
    with heartbeat("anything", None, interval=0.01):
        time.sleep(0.03)
    assert capsys.readouterr() == ("", "")
    lines = []  # the same work with a reporter does speak: the silence above is the None
    with heartbeat("anything", lines.append, interval=0.01):
        time.sleep(0.03)
    assert lines and capsys.readouterr() == ("", "")
