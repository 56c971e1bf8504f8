"""The runs of ``passive-assoc reproduce wavelet`` (:mod:`.wavelet`): the methods compared,
one run's scores, their summaries over runs, and the worker pool the runs are spread over.
The 2-D demo (:mod:`.wavelet_passive`) and the printed tables (:mod:`.wavelet_report`) build
on these."""

from __future__ import annotations

import multiprocessing
import sys
import warnings
from collections.abc import Callable
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from .._settings import KalmanInit
from ..data import TrackTable
from ..distributed import current_client
from ..radar_esm import (
    Chi2TrackAssociator,
    RadarEsmAssociation,
    WaveletChi2Associator,
    WaveletFuzzyAssociator,
    filter_reports,
)
from ..radar_esm.baselines import position_gate_pairs
from ..simulation.radar_esm import PAPER_WAVELET_PHASES, PAPER_WAVELET_TARGETS, paper_wavelet_scenario
from ..track_association import NearestNeighbourAssociator, TrackAssociation
from .common import map_runs

#: The paper's correct-association probabilities (its §5), as ranges over scans.
PAPER = {"wavelet": (0.88, 0.93), "nearest": (0.72, 0.85)}
#: The ablations: run on the scenes without false tracks (and in the 2-D demo) only, where the
#: acceptance reads them; the clutter sweep compares the four methods.
ABLATIONS = ("wavelet_paper", "wavelet_per_scan", "wavelet_literal", "wavelet_raw", "combined_raw")
#: Methods in print order, with their column titles.
METHODS = {
    "wavelet": "wavelet-fuzzy",
    "nearest": "nearest nb.",
    "chi2": "χ² test",
    "combined": "combined",
    "wavelet_paper": "τ = 0.5",
    "wavelet_per_scan": "per-scan Σ",
    "wavelet_literal": "literal stat.",
    "wavelet_raw": "w.-f., reports",
    "combined_raw": "comb., reports",
}
#: The methods given the sensors' raw reports instead of the filtered tracks (they filter them
#: themselves, and their coarse gate reads the reports).
RAW = ("wavelet_raw", "combined_raw")
N_TARGETS = len(PAPER_WAVELET_TARGETS)
#: Scans 6–30 (1-based): the mean the paper's range is compared with.
SCORED = slice(5, None)
#: Scans 15–30, where the acceptance wants every scan ≥ 0.88.
LATE = slice(14, None)


def maneuver_power(period: float = 1.0) -> float:
    """The targets' mean squared acceleration change per second, m²/s⁵: the white-jerk
    density whose integral over the run matches the truth's jumps on average (Table 1)."""
    jumps = np.diff(PAPER_WAVELET_TARGETS[:, 1:], axis=1)
    return float(np.mean(np.sum(jumps**2, axis=1)) / (sum(PAPER_WAVELET_PHASES) * period))


#: The trackers' process noise q (≈ 169 m²/s⁵), from :func:`maneuver_power`.
PROCESS_NOISE = maneuver_power()


class Associator(Protocol):
    def associate(self, *, local: TrackTable, system: TrackTable) -> TrackAssociation: ...


@dataclass(frozen=True)
class Settings:
    """What a run needs besides its seed and clutter level: the trackers' q and start, the
    coarse window and gate probability, and whether the ablations run."""

    process_noise: float = PROCESS_NOISE
    window: int | None = None
    gate_probability: float = 0.99
    ablations: bool = True
    init: KalmanInit = "single_point"


#: The nearest-neighbour baseline's position χ² gate.
NEAREST_GATE_PROBABILITY = 0.99


def methods(settings: Settings) -> dict[str, Associator]:
    """The associators compared, one thread each (runs are parallel instead), all with their
    defaults but the coarse window and gate probability: the wavelet-fuzzy method reads its
    process noise back from the tracks (the trackers' q, so that its window covariance includes
    the filtered errors' scan-to-scan correlation); the combined decision (the project's
    extension); ``τ = 0.5`` the wavelet-fuzzy method with METHODS' reading of τ
    (:meth:`WaveletFuzzyAssociator.paper`); the two gate ablations: Σ diagonal in time
    (whitened), and the paper's literal scalar statistic; and the wavelet-fuzzy method and the
    combined decision given the raw reports (filtered inside with the trackers' q)."""

    def wavelet(**changes: object) -> WaveletFuzzyAssociator:
        return WaveletFuzzyAssociator(
            **{"window": settings.window, "gate_probability": settings.gate_probability, "n_threads": 1, **changes}  # type: ignore[arg-type]
        )

    compared: dict[str, Associator] = {
        "wavelet": wavelet(),
        "nearest": NearestNeighbourAssociator(gate_probability=NEAREST_GATE_PROBABILITY, n_threads=1),
        "chi2": Chi2TrackAssociator(),
        "combined": WaveletChi2Associator(window=settings.window, n_threads=1),
    }
    if settings.ablations:
        compared["wavelet_paper"] = wavelet(tau=0.5)
        compared["wavelet_per_scan"] = wavelet(process_noise=None)
        compared["wavelet_literal"] = wavelet(whitened=False, process_noise=None)
        compared["wavelet_raw"] = wavelet(process_noise=settings.process_noise)
        compared["combined_raw"] = WaveletChi2Associator(
            window=settings.window, process_noise=settings.process_noise, n_threads=1
        )
    return compared


@dataclass(frozen=True)
class RunScores:
    """One run: per method, the fraction of targets correctly paired at each scan (NaN at
    scans without tracks), the fraction of true pairs that passed the method's gate, and (the
    wavelet-fuzzy method) the fraction that passed it with a similarity above ε."""

    correct: dict[str, NDArray[np.float64]]
    gate_keeps: dict[str, NDArray[np.float64]]
    above_epsilon: NDArray[np.float64] | None = None


def _truth_of(tracks: TrackTable) -> NDArray[np.int64]:
    """Lookup id → truth label (−2 for ids not in the table)."""
    assert tracks.truth is not None
    lookup = np.full(int(tracks.track.max(initial=-1)) + 1, -2, np.int64)
    lookup[tracks.track] = tracks.truth
    return lookup


def true_pair_fraction(
    pairs_time: NDArray[np.float64],
    local: NDArray[np.int64],
    system: NDArray[np.int64],
    radar: TrackTable,
    esm: TrackTable,
    scan_times: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Per scan, how many of the listed (ESM, radar) pairs are true target pairs, over
    :data:`N_TARGETS`; NaN at scans where the radar has no track."""
    truth_r, truth_e = _truth_of(radar), _truth_of(esm)
    label = truth_r[system]
    true = (label >= 0) & (label == truth_e[local])
    scan = np.searchsorted(scan_times, pairs_time[true])
    out = np.bincount(scan, minlength=len(scan_times)) / N_TARGETS
    return np.where(np.isin(scan_times, radar.time), out, np.nan)


def score(
    result: TrackAssociation, radar: TrackTable, esm: TrackTable, times: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(correct fraction per scan, true pairs kept by the gate per scan) of one result. The
    gate's pairs are the result's candidates (the radar/ESM methods list them); for the
    nearest-neighbour associator, the pairs its position χ² gate passes."""
    p = result.pairs
    if isinstance(result, RadarEsmAssociation):
        c = result.candidates
    else:
        c = position_gate_pairs(local=esm, system=radar, gate_probability=NEAREST_GATE_PROBABILITY)
    return (
        true_pair_fraction(p.time, p.local_track, p.system_track, radar, esm, times),
        true_pair_fraction(c.time, c.local_track, c.system_track, radar, esm, times),
    )


def run_once(seed: np.random.SeedSequence, n_clutter: int, settings: Settings) -> RunScores:
    scenario = paper_wavelet_scenario(np.random.default_rng(seed), n_clutter=n_clutter)
    tracks = filter_reports(scenario.measurements, settings.process_noise, init=settings.init, n_threads=1)
    radar, esm = tracks.of(0), tracks.of(1)
    correct, keeps, above = {}, {}, None
    for name, method in methods(settings).items():
        if name in RAW:
            raw_radar, raw_esm = scenario.measurements.of(0), scenario.measurements.of(1)
            result = method.associate(local=raw_esm, system=raw_radar)
            correct[name], keeps[name] = score(result, raw_radar, raw_esm, scenario.scan_times)
            continue
        result = method.associate(local=esm, system=radar)
        correct[name], keeps[name] = score(result, radar, esm, scenario.scan_times)
        if name == "wavelet":
            assert isinstance(method, WaveletFuzzyAssociator) and isinstance(result, RadarEsmAssociation)
            c = result.candidates
            chosen = c.score > method.epsilon
            above = true_pair_fraction(
                c.time[chosen], c.local_track[chosen], c.system_track[chosen], radar, esm, scenario.scan_times
            )
    return RunScores(correct, keeps, above)


def summarise(runs: list[RunScores]) -> dict[str, Any]:
    """Per method: the per-scan mean over runs, its mean over scans 6–30, its minimum over
    scans 15–30, and the share of true pairs the gate kept over scans 6–30."""
    out: dict[str, Any] = {}
    for name in runs[0].correct:
        per_scan = mean_over_runs([r.correct[name] for r in runs])
        kept = mean_over_runs([r.gate_keeps[name] for r in runs])
        out[name] = {
            "per_scan": per_scan,
            "mean_6_30": float(np.mean(per_scan[SCORED])),
            "min_15_30": float(np.min(per_scan[LATE])),
            "gate_keeps_true_6_30": float(np.mean(kept[SCORED])),
        }
        if name == "wavelet" and runs[0].above_epsilon is not None:
            above = mean_over_runs([r.above_epsilon for r in runs if r.above_epsilon is not None])
            out[name]["losses"] = losses(out[name]["per_scan"], kept, above)
    return out


def losses(
    correct: NDArray[np.float64], kept: NDArray[np.float64], above: NDArray[np.float64]
) -> dict[str, dict[str, float]]:
    """Where the targets not correctly paired went, as shares of all targets, over scans 6–14
    and 15–30: true pair gated out; passed the gate with f ≤ ε; above ε but another pair of
    either track was chosen first (the repeated maximum)."""
    parts = {"gated_out": 1.0 - kept, "below_epsilon": kept - above, "beaten": above - correct}
    spans = {"6_14": slice(5, 14), "15_30": LATE}
    return {name: {k: float(np.mean(v[span])) for k, v in parts.items()} for name, span in spans.items()}


def mean_over_runs(values: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """Per-scan mean over runs, NaN (silently) where no run has a value."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        out: NDArray[np.float64] = np.nanmean(np.array(values), axis=0)
    return out


#: One run: ``run(seed, *arguments)``, a module-level function (worker processes pickle it by name).
Run = Callable[..., Any]


def run_chunk(task: tuple[Run, list[np.random.SeedSequence], tuple[Any, ...]]) -> list[Any]:
    """``run(seed, *arguments)`` for a list of seeds, in one process (:func:`run_once`, or the
    2-D demo's :func:`.wavelet_passive.demo_run`)."""
    run, seeds, arguments = task
    return [run(s, *arguments) for s in seeds]


def worker_pool(workers: int) -> AbstractContextManager[Executor | None]:
    """Worker processes (spawned: the Rust core's thread pool does not survive a fork), or
    None to run in this process. Most of a run is NumPy-sized Python, so threads would queue
    on the GIL."""
    client = current_client()
    if client is not None:  # --scheduler: the cluster's executor
        return nullcontext(client.get_executor())
    if workers <= 1:
        return nullcontext(None)
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))


Submitted = tuple[list[Future[list[Any]]], list[list[int]]]


def submit_seeds(
    pool: Executor, run: Run, seeds: list[np.random.SeedSequence], arguments: tuple[Any, ...]
) -> Submitted:
    """:func:`run_chunk` over every seed, in up to 64 chunks, queued on ``pool``."""
    chunks = [c.tolist() for c in np.array_split(np.arange(len(seeds)), min(len(seeds), 64))]
    futures = [pool.submit(run_chunk, (run, [seeds[r] for r in chunk], arguments)) for chunk in chunks]
    return futures, chunks


def collect(submitted: Submitted, desc: str) -> list[Any]:
    """The results of :func:`submit_seeds`, in seed order, with a progress bar."""
    out: list[Any] = []
    futures, chunks = submitted
    with tqdm(total=sum(map(len, chunks)), desc=desc, unit="run", file=sys.stderr, disable=None, leave=False) as bar:
        for future, chunk in zip(futures, chunks, strict=True):
            out.extend(future.result())
            bar.update(len(chunk))
    return out


def map_seeds(
    pool: Executor | None, run: Run, seeds: list[np.random.SeedSequence], arguments: tuple[Any, ...], desc: str
) -> list[Any]:
    """``run(seed, *arguments)`` over every seed, in seed order, with a progress bar."""
    if pool is None:
        return map_runs(lambda r: run(seeds[r], *arguments), len(seeds), 1, desc)
    return collect(submit_seeds(pool, run, seeds, arguments), desc)
