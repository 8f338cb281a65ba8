"""The check's part labels count up on the console whichever thread starts a part first
(:class:`railcheck.check.workers.Starts`): each number is given and announced in one step."""

import threading
import time

from railcheck.check.workers import Starts


def test_parts_started_on_racing_threads_are_announced_in_the_order_of_their_numbers():
    lines: list[str] = []

    def say(msg):
        time.sleep(0.001)  # a slow console: a second thread would overtake an unlocked one
        lines.append(msg)

    starts = Starts(8, say)
    labels: dict[str, str] = {}
    go = threading.Barrier(8)

    def start(name):
        go.wait()
        labels[name] = starts.label(name)

    threads = [threading.Thread(target=start, args=(f"part{i}",)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [line.split(")")[0] for line in lines] == [f"({k}/8" for k in range(1, 9)]
    assert sorted(labels.values()) == sorted(line.removesuffix(": started") for line in lines)
    assert all(line.endswith(": started") for line in lines)
