"""Shared by the module's tests: does a second Python thread keep running while `work` runs?"""
import threading
import time


def assert_gil_released(work):
    """Runs work() while a second thread ticks every millisecond; fails unless the work took a while and the
    ticker advanced during it (the GIL was released)."""
    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    try:
        start = time.perf_counter()
        work()
        end = time.perf_counter()
    finally:
        done.set()
        t.join()
    during = [x for x in ticks if start < x < end]
    assert end - start > 0.05, "the work must take a while for this test to mean anything"
    assert len(during) >= 10, f"only {len(during)} ticks in {end - start:.3f} s: the GIL was held"
