"""Fuzzy track initiation for distributed passive sensors (METHODS §1, paper 000).

From the raw azimuth/elevation (or bearing) measurements of two or more sensors over several
scans, in clutter, and without knowing the clutter density or the detection probability,
:class:`FuzzyTrackInitiator` finds how many constant-velocity targets there are, which
measurements are theirs, and their initial states. The pipeline (candidate generation with
pruning, Gauss-Newton candidate fits, steepest ascent of the fuzzy closeness R, detection,
ambiguity resolution, final ML fit) runs in the Rust core with the GIL released.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from itertools import combinations
from typing import Annotated, Any, Literal

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._inputs import check_pair
from .._params import Boolean, Configurable, Epoch, Interval, Options, checked
from .._progress import ProgressArg, reporting
from .._validation import as_int_array
from .._warn import warn_at_caller
from ..data import MeasurementTable, SensorNetwork
from ..outcome import COMPLETED, Outcome
from .diagnostics import STAGE_COUNT_NAMES, STAGE_SECOND_NAMES, empty_stage, limit_message, warn_if_no_candidate
from .regroup import Found, Neighbourhood, regroup
from .score import MIN_SCORE, ScoreTerms, track_scores

#: χ² with 2 degrees of freedom (8 equations, 6 unknowns) at 99.9 %: the default gate on a
#: 3-D candidate's fit.
CHI2_2DOF_999 = 13.815510557964274


#: A finite number > 0.
POSITIVE = Interval(float, 0.0, None, closed="neither")
#: A count of at least one.
COUNT = Interval(int, 1, None)


@dataclass(frozen=True)
class InitiatedTrack:
    """One initiated target.

    Attributes
    ----------
    state : ndarray, shape (D,)
        ML estimate of the constant-velocity initial state X0 at ``t0`` (D = 6 in 3-D, 4 in 2-D).
    covariance : ndarray, shape (D, D)
        Inverse Fisher information at ``state``.
    closeness : float
        Fuzzy synthetic closeness R at ``state`` (eq. 18).
    chi2 : float
        Sum of squared normalised residuals of the final fit.
    measurements : ndarray of int
        Rows of the input table assigned to this target.
    score : float
        Log-likelihood ratio of the rows being this target rather than clutter (natural log;
        :mod:`passive_assoc.fti.score`): the larger, the surer. Tracks below the initiator's
        ``min_score`` are not returned.
    """

    state: NDArray[np.float64]
    covariance: NDArray[np.float64]
    closeness: float
    chi2: float
    measurements: NDArray[np.int64]
    score: float


@dataclass(frozen=True)
class InitiationDiagnostics:
    """How the pipeline got there: candidates left after each stage, descent iterations and
    seconds per stage, summed over the passes (``candidate_scans`` > 1 runs a second pass).

    Attributes
    ----------
    stage_counts : dict of str to int
        In pipeline order: ``raw`` (4-tuples of the outer scans), ``ray_gate``, ``behind``,
        ``v_max`` (left after each pruning rule), ``fitted`` (fits with a finite estimate),
        ``chi2_gate``, ``supported`` (kept by the support gate), ``optima`` (descents run: as
        ``supported`` unless a pass searched in stages, ``search_stage``), ``merged`` (optima
        after merging) and ``detected`` (targets detection accepted; the final tests may
        dissolve some and regrouping replace some, so ``len(tracks)`` can differ).
    descent_iterations : ndarray of int
        Iterations of each descent, in candidate order.
    stage_seconds : dict of str to float
        Wall-clock seconds of ``candidates``, ``fit``, ``support`` (the re-gating between
        stages included), ``descent``, ``detection``, ``final`` (the final fits and tests)
        and ``regroup`` (``regroup``'s initiations, which the other stages leave out; 0
        without it).
    candidates : {"paper", "rounds", "witnessed"}
        The candidate formation that ran (``candidates="auto"`` resolved).
    limit : str or None
        The limit that ended the candidate formation early (``on_limit="warn"``), as the
        error it would otherwise have been; None when the formation ran to its end (the
        sweep's own budget, see ``sweep``, is never reported here).
    below_min_score : int
        Tracks the pipeline found whose score was below ``min_score``: their measurements are
        clutter in the result.
    regrouped : int
        Tracks that regrouping (``regroup``) replaced; 0 without it.
    limit_slots : tuple of (int, int) or None
        With ``limit``: the formation's scan slots (sensor pair and scan quadruple) formed in
        full before it stopped, and all of its slots; None without a limit.
    """

    stage_counts: dict[str, int]
    descent_iterations: NDArray[np.int64]
    stage_seconds: dict[str, float]
    candidates: Literal["paper", "rounds", "witnessed"]
    limit: str | None
    below_min_score: int
    regrouped: int = 0
    limit_slots: tuple[int, int] | None = None


@dataclass(frozen=True)
class InitiationResult(Outcome):
    """Output of :meth:`FuzzyTrackInitiator.initiate`.

    Every input measurement is in exactly one track or in :attr:`clutter`; :attr:`labels`
    holds that partition as one array (track index, or -1 for clutter).

    :attr:`termination` is ``"completed"``; ``"no_candidates"`` when pruning left no
    candidate (:attr:`message` names the stage that emptied and its usual cause; a warning
    says the same); or ``"candidate_limit"`` when the formation reached ``max_candidates``
    and stopped there (``on_limit="warn"``): the tracks are those found until then,
    :attr:`success` is False and :attr:`message` and a warning name the limit.
    """

    tracks: list[InitiatedTrack]
    labels: NDArray[np.int64]
    t0: float
    diagnostics: InitiationDiagnostics = field(repr=False)

    @property
    def clutter(self) -> NDArray[np.int64]:
        """Rows assigned to no track."""
        return np.flatnonzero(self.labels < 0)

    @property
    def states(self) -> NDArray[np.float64]:
        """All track states stacked, shape (n_tracks, D)."""
        if not self.tracks:
            return np.empty((0, 0))
        return np.stack([t.state for t in self.tracks])


@dataclass(frozen=True)
class FuzzyTrackInitiator(Configurable):
    """Fuzzy track initiator with the paper's defaults.

    Parameters
    ----------
    spread_factor : float
        Membership spread per sensor and angle as a multiple of that sensor's noise std:
        ``s = spread_factor * sigma``. The paper uses ``s = 2 sigma`` (10 mrad at 5 mrad).
    spread : float, optional
        A fixed spread in radians for every sensor and angle, overriding ``spread_factor``.
    gate_sigmas : float
        Detection gate g of eq. 23, in standard deviations (a σ-gate on each measurement's
        normalised residual); paper 5.
    n_detect : int, optional
        Nd: an optimum becomes a target when more than this many not-yet-taken measurements
        are related to it. Default: from the data, ``ceil(0.6 * N) - 1`` for N scans in the
        table (summed over sensors; a target yields at most one report per scan), which is the
        paper's 9 for its 2 sensors x 8 scans and grows with sensors and scans
        (docs/methods.md §1 has the measurements).
    pairs : sequence of (int, int), optional
        Sensor pairs that generate candidates; default every pair. With many sensors every
        target has candidates from every pair, and the candidates are most of the time: the
        neighbouring pairs ``[(0, 1), (1, 2), ...]`` of a line of five sensors found as many
        targets in a quarter to two thirds of the time on the scale bench's scenes
        (docs/performance.md, *Fewer sensor pairs*; not measured at Pd < 1).
    candidates : {"auto", "paper", "rounds", "witnessed"}
        Where the candidates come from. ``"paper"``: the first and last scans of each sensor
        pair (eq. 20–22), whose 4-tuples grow as the fourth power of the targets.
        ``"rounds"`` (a project extension): two neighbouring scans of each sensor pair, each
        candidate tested against the pair's neighbouring scans and the other sensors' scans
        before its fit, so that the fits grow as the square of the targets. ``"witnessed"``
        (a project extension): the paper's scans, each candidate tested before its fit
        against every scan of the sensors outside its pair, or, with fewer than three sensors
        that scan twice or more, against the pair's own other scans, as many of which must see
        it as detection will need (on the paper's scene and its grown forms it finds the paper
        formation's targets from an eighth to a fiftieth of the fits). ``"auto"`` (default):
        with three or more sensors, ``"rounds"`` in 3-D and ``"witnessed"`` in 2-D, where a
        third sensor's rays reject the pair's ghosts; ``"witnessed"`` with fewer.
        The result's diagnostics say which ran (docs/methods.md §1, *Candidate formation*).
    prefit_gates : bool
        The rounds and witnessed formations' tests before each fit (the pair's neighbouring
        scans, the other sensors' scans); False fits every candidate that passes ``v_max``.
    sweep : bool
        After the rounds formation, the paper's formation on the rows its tracks leave as
        clutter, with a twentieth of ``max_candidates`` as its budget: it finds the targets a
        missed detection left without a slot of rounds (docs/methods.md §1, *Sweep after the
        rounds*). Reaching that budget ends the sweep silently (no warning; ``termination``
        and ``diagnostics.limit`` speak of ``max_candidates`` only); it does not run when the
        rounds reached ``max_candidates``. False skips it (at 20 targets and fewer it is most
        of the fitted candidates).
    untangle : bool
        At the end, two tracks that compete for rows exchange one sensor's rows (from one of
        its scans on) when both then fit better, by a summed chi-square drop above 2: where
        two targets fly close, each track can hold the other's rows at one sensor
        (docs/methods.md §1, *Untangling*). False keeps the classification's assignment.
    ray_gate_sigmas : float or None
        Prune a pair of first- or last-scan rays whose closest approach exceeds this many
        standard deviations of the crossing, plus ``v_max`` times the two sensors' time
        offset (asynchronous sensors; 3-D only, 2-D lines always meet); None: off.
    reject_behind : bool
        Prune ray pairs that meet behind either sensor.
    v_max : float or None
        Prune candidates whose implied speed exceeds this (m/s); None switches it off. The
        default, 500 m/s, is 2.5x the paper's fastest target; raise it for faster targets
        (more candidates then reach the fitting stage).
    chi2_gate : float or None
        Prune candidates whose 4-measurement fit has χ² above this value (a χ² gate, not in
        σ; 3-D: 2 dof); None: off.
    one_per_scan : bool
        A target takes at most one measurement per sensor and scan (the closest), as a
        sensor reports a target once per scan.
    detection_order : {"membership", "closeness"}
        The order in which detection (eq. 23) visits the optima. ``"closeness"`` is the
        paper's, by decreasing closeness R, which favours an optimum between targets (it
        gathers membership from all their measurements). ``"membership"`` (default; a project
        extension) takes first the optimum whose measurements it would take now have the largest
        summed membership, re-ranking as they are taken (docs/methods.md §1, *Detection order*).
    merge_tol : float
        Optima closer than this, in units of the candidate fit's standard deviations, are one.
    descent_scaling : {"whitened", "diagonal"}
        Coordinates of the steepest-ascent search. ``"diagonal"`` scales each component by the
        candidate fit's standard deviation (METHODS §1 wording). ``"whitened"`` (default) uses
        the candidate fit's full covariance factor ``L`` (``x = x_c + L y``), which also removes
        the strong position–velocity and along-range correlations of a 4-measurement fit, so
        a search needs fewer closeness evaluations (``python benches/bench_search.py``;
        docs/performance.md) with the same detection results
        (``passive-assoc reproduce fti --descent-scaling diagonal``).
    descent_max_iter : int
        Iteration cap of each steepest-ascent search.
    refine_passes : int
        Extra passes that re-relate measurements (eq. 23–24) to the final ML estimates and
        refit, until the partition stops changing (a project extension; 0 = the paper's
        pipeline). The ML estimate is sharper than the closeness optimum the first
        classification uses, which matters where targets cross or fly close.
    candidate_scans : int
        How far into each end of the window candidates reach (a project extension for missed
        detections). 1 is the paper: each sensor's first and last scan only, so a target missed
        in either is never initiated. With k > 1 a second pass, on the measurements the first
        pass's detection left, also pairs each sensor's i-th scan from the start with its j-th
        from the end for every other i, j < k. Default 4 (docs/methods.md §1 has the
        measurements behind it).
    support_gate : bool
        Descend only from candidates that more than ``n_detect`` scans support: a scan supports
        a candidate when one of its measurements is within ``gate_sigmas`` of the predicted
        angles, with the candidate fit's own uncertainty added (a project extension; False =
        the paper, every candidate is searched). Such a candidate cannot become a target, and
        in 2-D, where four bearings fit exactly and no χ² gate exists, nearly every candidate
        is of that kind. The gate also follows each candidate as a tracker would, and requires
        the measurements it finds to be at least as likely from it as from clutter at the
        scan's local density (docs/methods.md §1, *Tracking gate*).
    gate_pd : float or None
        Detection probability the tracking gate assumes when a scan's gate holds no
        measurement: each such miss adds ``log(1 - gate_pd)`` (negative) to the candidate's
        score, as a target is missed there with probability ``1 - gate_pd`` and clutter always
        is (a project extension, opt-in; None: misses are not priced). On dense 2-D scenes it
        removes most clutter tracks; docs/methods.md §1 (*Misses priced*) has the measurements
        and what it costs at low Pd. Default None.
    search_stage : int or None
        Candidates searched before detection runs (a project extension). A pass with more
        candidates than this searches them in stages: by decreasing tracking-gate score (how
        much likelier the measurements a candidate's walk took are from it than from clutter),
        ``search_stage`` at a time, with detection run over every optimum so far after each
        stage; later stages search only the candidates that still pass the support gate on the
        measurements detection has left. Scenes that reach tens of thousands of candidates
        (many sensors and targets) then search little more than one stage of them. None:
        every candidate is searched first, as in the paper. Default 8192, above the candidates
        of the paper's scene and of the 2-D scenes the defaults are tuned on, so their
        results are those of the paper's order (docs/performance.md, *Initiation at scale*).
    track_test : float or None
        Dissolve a final track whose ML refit χ² is above the χ²(dof) quantile at this tail
        probability (dof = angles − state dimension); its measurements become clutter (a
        project extension; None: off). A track threaded through clutter has residuals spread
        over the whole gate (χ²/dof near 8); a target's are noise. With it on, a track seen in
        far fewer of its sensors' scans than the scene's median track is dissolved too (the
        coverage test), and the second candidate pass may reuse the measurements of first-pass
        tracks the test dissolves (docs/methods.md §1). Default 1e-6.
    max_candidates : int
        Stop the candidate formation (``on_limit``) rather than run for long when more
        candidates than this reach the fitting stage in one pass, or rather than run for
        minutes when pairing one scan pair's first-scan and last-scan ray pairs would take
        more than 200 times this many tests (the count is known before any test is made).
        A count, so that the answer does not depend on the machine or its load; in time, a
        candidate that reaches the fits costs the call about 4–10 µs on two cores with the
        tests that formed it and its gates (the 200-target scenes of docs/performance.md;
        ``benches/bench_initiation_scaling.py`` prints the limit's message for each),
        so the default is a few seconds of candidate formation, and a limit reached reports
        this call's own seconds, µs a candidate and how far through its scan slots the
        formation got. In memory, it grows slowly: the support gate keeps a few candidates in
        a thousand (past ``search_stage`` at 48 bytes each), and on the 200-target scenes the
        peak RSS was 102–122 MB at the default and 123–212 MB at 2 000 000, the formation
        getting further; ``support_gate=False`` keeps every fitted candidate, at about 0.45
        kB (225 MB at the default). At 5 sensors × 100 targets the default leaves room for 30
        times the candidates the formation fits.
    on_limit : {"warn", "raise"}
        What reaching ``max_candidates`` does. ``"warn"`` (default): the formation stops
        there, the search runs on the candidates fitted so far, and the result returns the
        tracks they found, with termination ``"candidate_limit"``, the limit named in its
        message and in a warning. ``"raise"``: a ValueError naming the limit, nothing returned.
        The sweep after the rounds (``sweep``) stops at its own budget either way, silently.
    regroup : bool
        3-D only. After the pipeline, each track's measurements are initiated again with the
        free measurements whose lines of sight meet theirs, and the track is replaced by the
        tracks found there when their summed score is higher by more than 5 and by more than
        the free rows they take score alone (a project extension, opt-in; up to four passes).
        Where many targets share three or four sensors' sky, a ghost made of several targets'
        rows can be accepted first and leave those targets unfound; this finds them
        (docs/methods.md §1, *Regrouping*, has the measurements), at the cost of an
        initiation per track and pass: two to five times the time of the call. Default False.
    score_pd : float
        Detection probability the track score assumes (each of a sensor's scans without the
        track's measurement costs ``log(1 - score_pd)``). Default 0.9.
    min_score : float or None
        Tracks whose score (:attr:`InitiatedTrack.score`) is below this are not returned;
        their measurements become clutter. None keeps every track. The default,
        :data:`MIN_SCORE`, is calibrated on simulation (docs/methods.md §1, *Track score*).
    n_threads : int, optional
        Threads; default all cores. Results are identical for any value.
    """

    spread_factor: Annotated[float, POSITIVE] = 2.0
    spread: Annotated[float | None, POSITIVE, None] = None
    gate_sigmas: Annotated[float, POSITIVE] = 5.0
    n_detect: Annotated[int | None, COUNT, None] = None
    pairs: Sequence[tuple[int, int]] | None = None  # checked against the network at initiate()
    candidates: Annotated[
        Literal["auto", "paper", "rounds", "witnessed"], Options("auto", "paper", "rounds", "witnessed")
    ] = "auto"
    prefit_gates: Annotated[bool, Boolean()] = True
    sweep: Annotated[bool, Boolean()] = True
    untangle: Annotated[bool, Boolean()] = True
    ray_gate_sigmas: Annotated[float | None, POSITIVE, None] = 5.0
    reject_behind: Annotated[bool, Boolean()] = True
    v_max: Annotated[float | None, POSITIVE, None] = 500.0
    chi2_gate: Annotated[float | None, POSITIVE, None] = CHI2_2DOF_999
    one_per_scan: Annotated[bool, Boolean()] = True
    detection_order: Annotated[Literal["membership", "closeness"], Options("membership", "closeness")] = "membership"
    merge_tol: Annotated[float, POSITIVE] = 1.0
    descent_scaling: Annotated[Literal["whitened", "diagonal"], Options("whitened", "diagonal")] = "whitened"
    descent_max_iter: Annotated[int, COUNT] = 100
    refine_passes: Annotated[int, Interval(int, 0, None)] = 2
    candidate_scans: Annotated[int, COUNT] = 4
    support_gate: Annotated[bool, Boolean()] = True
    gate_pd: Annotated[float | None, Interval(float, 0.0, 1.0, closed="neither"), None] = None
    search_stage: Annotated[int | None, COUNT, None] = 8192
    track_test: Annotated[float | None, Interval(float, 0.0, 0.5, closed="neither"), None] = 1e-6
    max_candidates: Annotated[int, COUNT] = 500_000
    on_limit: Annotated[Literal["warn", "raise"], Options("warn", "raise")] = "warn"
    regroup: Annotated[bool, Boolean()] = False
    score_pd: Annotated[float, Interval(float, 0.0, 1.0, closed="neither")] = 0.9
    min_score: Annotated[float | None, Interval(float, None, None), None] = MIN_SCORE
    n_threads: Annotated[int | None, COUNT, None] = None

    def _pairs(self, n_sensors: int) -> NDArray[np.int64]:
        if self.pairs is None:
            chosen = list(combinations(range(n_sensors), 2))
        else:
            chosen = list(self.pairs)
        if not chosen:
            raise ValueError(
                "pairs: at least one sensor pair is needed (the network has "
                f"{n_sensors} sensor{'s' if n_sensors != 1 else ''})"
            )
        return as_int_array("pairs", np.asarray(chosen), shape=(None, 2))

    def _spreads(self, sensors: SensorNetwork) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        n = sensors.n_sensors
        if self.spread is not None:
            return np.full(n, self.spread), np.full(n, self.spread)
        sigma_el = sensors.sigma_azimuth if sensors.ndim == 2 else sensors.sigma_elevation
        return self.spread_factor * sensors.sigma_azimuth, self.spread_factor * np.asarray(sigma_el, dtype=float)

    @checked
    def initiate(
        self,
        measurements: MeasurementTable,
        sensors: SensorNetwork,
        *,
        t0: Epoch = None,
        progress: ProgressArg = None,
    ) -> InitiationResult:
        """Find the targets in ``measurements``.

        Parameters
        ----------
        measurements : MeasurementTable
            Every measurement of every sensor in the window (any order, any number of scans;
            candidates come from each sensor's outermost scans, see ``candidate_scans``).
        sensors : SensorNetwork
        t0 : float, optional
            Epoch of the returned initial states; default the earliest measurement time.
        progress : bool or callable, optional
            A progress bar on stderr (each pass's candidate formation and search): None shows
            it on a terminal once the call has run 2 s, True always, False never. A callable
            gets the reports instead, ``progress(stage, fraction)`` (stages ``"candidates"``
            and ``"search"``, once per pass, each from 0 to 1; at most one every 0.2 s within
            a stage; then ``"regroup"`` with ``regroup=True``, once a track), on one of the
            call's threads; raising in it stops the call, and is raised.

        Returns
        -------
        InitiationResult
        """
        table, network = check_pair(measurements, sensors)
        epoch = float(measurements.time.min()) if t0 is None else t0
        spread_az, spread_el = self._spreads(sensors)
        pairs, spreads = self._pairs(network.n_sensors), (spread_az, spread_el)
        if self.regroup and network.ndim != 3:
            raise ValueError(
                "regroup: only for 3-D networks (in the plane every two lines of sight meet, so a "
                "track's neighbourhood would be most of the table)"
            )
        with reporting(progress, "candidates") as report:
            out = _core.initiate(table, network, pairs, spreads, epoch, self, report)
            found, regrouped, started = Found.of(out), 0, time.perf_counter()
            if self.regroup:
                found, regrouped = self._regroup(found, table, network, pairs, spreads, epoch, report)
        scores = track_scores(found.labels, np.asarray(found.chi2), measurements, sensors, self.score_pd)
        kept = np.ones(len(scores), dtype=bool) if self.min_score is None else scores >= self.min_score
        labels = _renumbered(found.labels, kept)
        tracks = [
            InitiatedTrack(
                found.states[k],
                found.covariances[k],
                found.closeness[k],
                found.chi2[k],
                np.flatnonzero(found.labels == k),
                float(scores[k]),
            )
            for k in np.flatnonzero(kept)
        ]
        counts = {name: int(getattr(out.stage_counts, name)) for name in STAGE_COUNT_NAMES}
        seconds = {name: float(getattr(out.stage_seconds, name)) for name in STAGE_SECOND_NAMES}
        seconds["final"] = seconds.pop("final_fit")
        seconds["regroup"] = time.perf_counter() - started if self.regroup else 0.0
        below = int(len(kept) - kept.sum())
        diagnostics = InitiationDiagnostics(
            counts, out.descent_iterations, seconds, out.formation, out.limit, below, regrouped, out.limit_slots
        )
        emptied = empty_stage(counts)
        success = True
        if out.limit is not None:
            termination, success = "candidate_limit", False
            message = limit_message(out.limit, out.limit_slots, seconds, counts, len(tracks))
            warn_at_caller(message, LimitWarning)
        elif emptied is not None:
            termination, message = "no_candidates", emptied
            warn_if_no_candidate(emptied)
        else:
            termination, message = COMPLETED, f"{len(tracks)} track(s) initiated"
        return InitiationResult(
            tracks, labels, epoch, diagnostics, termination=termination, success=success, message=message
        )

    def _regroup(
        self,
        found: Found,
        table: MeasurementTable,
        network: SensorNetwork,
        pairs: NDArray[np.int64],
        spreads: tuple[NDArray[np.float64], NDArray[np.float64]],
        epoch: float,
        report: Callable[[str, float], object] | None,
    ) -> tuple[Found, int]:
        """Regrouping (``regroup``; module :mod:`.regroup`) of the pipeline's ``found``."""
        terms = ScoreTerms.of(found.labels, table, network, self.score_pd)
        near = Neighbourhood(table, network, self.ray_gate_sigmas, self.v_max)
        # Without the sweep: the track's own rows are there to start the rounds (module doc).
        local = dataclasses.replace(self, sweep=False)

        def initiate(rows: NDArray[np.int64]) -> Found:
            return Found.of(_core.initiate(table.select(rows), network, pairs, spreads, epoch, local, None))

        return regroup(found, terms, near, initiate, report)


class LimitWarning(UserWarning):
    """The candidate formation reached ``max_candidates`` and stopped there: the result holds
    the tracks found until then."""


def _renumbered(labels: NDArray[np.int64], kept: NDArray[np.bool_]) -> NDArray[np.int64]:
    """``labels`` with the rows of tracks not ``kept`` as clutter and the rest numbered
    0, 1, ... in their order."""
    new_index = np.full(len(kept) + 1, -1, dtype=np.int64)
    new_index[:-1][kept] = np.arange(int(kept.sum()))
    return new_index[labels]  # label -1 reads the last entry, -1


def initiate_tracks(
    measurements: MeasurementTable,
    sensors: SensorNetwork,
    *,
    t0: float | None = None,
    progress: ProgressArg = None,
    **settings: Any,
) -> InitiationResult:
    """Initiate tracks in one call: ``FuzzyTrackInitiator(**settings).initiate(measurements,
    sensors, t0=t0, progress=progress)``. The settings are :class:`FuzzyTrackInitiator`'s.

    >>> import passive_assoc as pa
    >>> scenario = pa.paper_fti_scenario(seed=1)
    >>> result = pa.initiate_tracks(scenario.measurements, scenario.sensors, progress=False)
    >>> result.termination, len(result.tracks)
    ('completed', 4)
    """
    return FuzzyTrackInitiator(**settings).initiate(measurements, sensors, t0=t0, progress=progress)
