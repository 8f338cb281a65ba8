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


def test_a_progress_line_wraps_at_the_console_width_on_a_terminal_and_stays_whole_in_a_pipe(capsys):
    """On a terminal a long line wraps within 100 columns under its message; a pipe or a log
    gets it whole (scripts and the tests that wait for a phrase read one line)."""
    from railcheck.progress import WIDTH, Progress, wrapped

    long = "[    0.1 s] solve      " + " ".join(["word"] * 60)
    lines = wrapped(long).splitlines()
    assert len(lines) > 1 and all(len(line) <= WIDTH for line in lines)
    assert all(line.startswith(" " * 23) for line in lines[1:])
    assert " ".join(line.strip() for line in lines) == long.strip()
    Progress().say("solve", " ".join(["word"] * 60))
    assert len(capsys.readouterr().err.splitlines()) == 1  # captured: not a terminal
