"""Calls from several Python threads run in parallel: the same work (formation location of the
5-sensor, 200-emitter scene with n_threads=1, 20 calls per thread) done by one thread twice, then
by two threads at once. The figures go to docs/performance.md.

    python benches/bench_concurrency.py
"""

from __future__ import annotations

import threading
import time

import passive_assoc as pa
from passive_assoc.simulation import formation_scene

CALLS = 20


def main() -> None:
    scene = formation_scene(1, n_sensors=5, n_emitters=200)
    locator = pa.FormationLocator(attribute_std=dict(scene.attribute_std), n_threads=1)

    def work() -> None:
        for _ in range(CALLS):
            locator.locate(scene.measurements, scene.sensors)

    work()  # warm-up: the thread's pool is built on its first call
    start = time.perf_counter()
    work()
    work()
    serial = time.perf_counter() - start
    threads = [threading.Thread(target=work) for _ in range(2)]
    start = time.perf_counter()
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    parallel = time.perf_counter() - start
    speed_up = serial / parallel
    print(f"2 x {CALLS} calls: one thread {serial:.3f} s, two threads {parallel:.3f} s, speed-up {speed_up:.2f}x")


if __name__ == "__main__":
    main()
