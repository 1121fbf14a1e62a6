"""Place-cell quality from a recording: place fields, localization, decoding, room cells,
recovery after kidnapping.

Labels (the nearest reference location, the region) and positions are used **only for
analysis**, never to learn the place cells. Whenever a read-out must be chosen (which unit is
the room cell, which location a unit stands for), it is chosen on the training part and scored
on the test part.

Units are assumed unit-variance on the training data (RCSFAICA outputs are), so thresholds such
as ICANN09's 4.5 are in training standard deviations.

The supervised ceiling (:mod:`~hippo.perception.ceiling`: what a ridge read-out of the same
state reaches) is re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hippo._checks import check_finite, check_int, check_real
from hippo.perception.ceiling import Ceiling as Ceiling
from hippo.perception.ceiling import ridge_ceiling as ridge_ceiling
from hippo.perception.ceiling import time_blocks as time_blocks
from hippo.perception.metric_checks import _check_labels, _check_Y

#: ICANN09: "ICA units which do not respond strongly enough (that is, less than 4.5) ..."
ICANN09_THRESHOLD = 4.5


#: the most bins per axis of a place-field grid (a grid of 1000 x 1000 bins per unit)
MAX_BINS = 1000


# ---------------------------------------------------------------------------- place fields
def _check_bins(bins: int | tuple[int, int]) -> tuple[int, int]:
    """``(nx, ny)`` from ``bins`` (one count for both axes, or a pair), each an integer in
    [1, :data:`MAX_BINS`]."""
    pair = (bins, bins) if np.ndim(bins) == 0 else tuple(bins)
    if len(pair) != 2:
        raise ValueError(f"bins must be an integer or a pair (nx, ny), got {bins!r}")
    nx, ny = (check_int("bins", b, lo=1, hi=MAX_BINS) for b in pair)
    return nx, ny


def place_fields_grid(xy: np.ndarray, Y: np.ndarray, *, bins: int | tuple[int, int] = 30,
                      extent: tuple[float, float, float, float] | None = None
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mean response of each unit on a spatial grid.

    Returns ``fields`` (units, ny, nx) (NaN where the robot never was), ``occupancy`` (ny, nx)
    in samples, and the bin edges ``xedges``, ``yedges``. ``extent`` is (xmin, xmax, ymin, ymax).
    """
    xy = check_finite("xy", xy)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"xy must be (T, 2), got {xy.shape}")
    Y = _check_Y(Y, xy.shape[0])
    if extent is None:
        extent = (xy[:, 0].min(), xy[:, 0].max() + 1e-9, xy[:, 1].min(), xy[:, 1].max() + 1e-9)
    nx, ny = _check_bins(bins)
    xe = np.linspace(extent[0], extent[1], int(nx) + 1)
    ye = np.linspace(extent[2], extent[3], int(ny) + 1)
    ix = np.clip(np.searchsorted(xe, xy[:, 0], side="right") - 1, 0, int(nx) - 1)
    iy = np.clip(np.searchsorted(ye, xy[:, 1], side="right") - 1, 0, int(ny) - 1)
    flat = iy * int(nx) + ix
    occ = np.bincount(flat, minlength=int(nx) * int(ny)).astype(float)
    sums = np.stack([np.bincount(flat, weights=Y[:, k], minlength=occ.size)
                     for k in range(Y.shape[1])])
    with np.errstate(invalid="ignore", divide="ignore"):
        fields = np.where(occ > 0, sums / occ, np.nan)
    return fields.reshape(Y.shape[1], int(ny), int(nx)), occ.reshape(int(ny), int(nx)), xe, ye


def place_fields_locations(labels: np.ndarray, Y: np.ndarray, n_locations: int) -> np.ndarray:
    """Mean response of each unit at each labelled location: (n_locations, units), NaN if the
    location was never visited."""
    lab = _check_labels(labels, n_locations)
    Y = _check_Y(Y, lab.size)
    cnt = np.bincount(lab, minlength=n_locations).astype(float)
    sums = np.stack([np.bincount(lab, weights=Y[:, k], minlength=n_locations)
                     for k in range(Y.shape[1])], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(cnt[:, None] > 0, sums / cnt[:, None], np.nan)


def _segments_cross(p: np.ndarray, q: np.ndarray, walls: np.ndarray) -> np.ndarray:
    """(P,) bool: does segment p[i]-q[i] properly cross any wall segment (n, 4)?"""
    a, b = walls[None, :, :2], walls[None, :, 2:]
    p, q = p[:, None, :], q[:, None, :]

    def orient(u, v, w):
        return np.sign((v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1])
                       - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0]))

    d1, d2 = orient(a, b, p), orient(a, b, q)
    d3, d4 = orient(p, q, a), orient(p, q, b)
    return np.any((d1 * d2 <= 0) & (d3 * d4 <= 0) & ~((d1 == 0) & (d2 == 0)), axis=1)


def location_neighbors(locations: np.ndarray, radius: float | None = None,
                       walls: np.ndarray | None = None) -> np.ndarray:
    """Boolean (L, L) matrix: locations "one step" apart (diagonal included).

    Two locations are neighbours if they lie within ``radius`` of each other and, when
    ``walls`` (an (n, 4) array ``x0, y0, x1, y1``, e.g. ``arena.wall_array()``) is given, no wall
    crosses the straight line between them (so cells on either side of a maze wall are not
    neighbours). Default radius: 1.5 × the median nearest-neighbour distance between locations.
    """
    loc = check_finite("locations", locations)
    if loc.ndim != 2 or loc.shape[1] != 2:
        raise ValueError(f"locations must be (L, 2), got {loc.shape}")
    L = loc.shape[0]
    d = np.linalg.norm(loc[:, None, :] - loc[None, :, :], axis=-1)
    if radius is None:
        if L < 2:
            return np.ones((L, L), bool)
        radius = 1.5 * float(np.median(np.sort(d, axis=1)[:, 1]))
    elif not check_real("radius", radius) > 0:
        raise ValueError(f"radius must be finite and > 0, got {radius!r}")
    nb = d <= radius
    if walls is not None and len(walls):
        w = check_finite("walls", walls)
        i, j = np.nonzero(np.triu(nb, 1))
        blocked = _segments_cross(loc[i], loc[j], w)
        nb[i[blocked], j[blocked]] = False
        nb[j[blocked], i[blocked]] = False
    return nb


# ---------------------------------------------------------------------------- localization
@dataclass
class Localization:
    """Per-unit localization (ICANN09 criterion), see :func:`localized_units`."""

    localized: np.ndarray       # (units,) bool
    peak: np.ndarray            # (units,) max response
    preferred: np.ndarray       # (units,) location with most supra-threshold samples (-1: none)
    concentration: np.ndarray   # (units,) fraction of supra-threshold samples near `preferred`
    n_active: np.ndarray        # (units,) number of supra-threshold samples

    @property
    def count(self) -> int:
        return int(self.localized.sum())


def localized_units(Y: np.ndarray, labels: np.ndarray, neighbors: np.ndarray, *,
                    threshold: float = ICANN09_THRESHOLD, min_concentration: float = 0.5,
                    min_samples: int = 3) -> Localization:
    """Which units are place cells (ICANN09): they respond ``>= threshold`` somewhere **and**
    code one location.

    "Codes one location" is made precise as: among the samples where the unit is at or above
    ``threshold``, at least ``min_concentration`` lie at the unit's preferred location (the most
    frequent label among them) or one step from it (``neighbors``), and there are at least
    ``min_samples`` such samples. A unit with a high peak that fires at several distant places
    (perceptual aliasing) is therefore not counted.
    """
    nb = np.asarray(neighbors, dtype=bool)
    if nb.ndim != 2 or nb.shape[0] != nb.shape[1]:
        raise ValueError(f"neighbors must be a square boolean matrix, got {nb.shape}")
    threshold = check_real("threshold", threshold)
    lab = _check_labels(labels, nb.shape[0])
    Y = _check_Y(Y, lab.size)
    k = Y.shape[1]
    peak = Y.max(axis=0) if Y.shape[0] else np.full(k, -np.inf)
    pref = np.full(k, -1)
    conc = np.zeros(k)
    n_act = np.zeros(k, int)
    for j in range(k):
        act = Y[:, j] >= threshold
        n_act[j] = int(act.sum())
        if n_act[j] == 0:
            continue
        counts = np.bincount(lab[act], minlength=nb.shape[0])
        pref[j] = int(np.argmax(counts))
        conc[j] = counts[nb[pref[j]]].sum() / n_act[j]
    loc = (peak >= threshold) & (n_act >= min_samples) & (conc >= min_concentration)
    return Localization(loc, peak, pref, conc, n_act)


def spatial_order(Y: np.ndarray, labels: np.ndarray, n_locations: int, *,
                  threshold: float = ICANN09_THRESHOLD) -> np.ndarray:
    """ICANN09's ordering of units for the activation map: by the location of their peak mean
    response; units that never reach ``threshold`` go to the end."""
    fields = place_fields_locations(labels, Y, n_locations)
    pref = np.nanargmax(np.where(np.isnan(fields), -np.inf, fields), axis=0)
    strong = np.asarray(Y).max(axis=0) >= threshold
    key = np.where(strong, pref, n_locations + pref)
    return np.argsort(key, kind="stable")


# ---------------------------------------------------------------------------- decoding
def fit_winner_decoder(Y: np.ndarray, labels: np.ndarray, n_locations: int) -> np.ndarray:
    """Map each unit to the location where it most often wins (argmax over units), learned on
    training data. Units that never win map to the most frequent location overall."""
    lab = _check_labels(labels, n_locations)
    Y = _check_Y(Y, lab.size)
    win = np.argmax(Y, axis=1)
    k = Y.shape[1]
    table = np.zeros((k, n_locations), int)
    np.add.at(table, (win, lab), 1)
    fallback = int(np.argmax(np.bincount(lab, minlength=n_locations))) if lab.size else 0
    return np.where(table.sum(axis=1) > 0, np.argmax(table, axis=1), fallback)


def decode_locations(Y: np.ndarray, mapping: np.ndarray) -> np.ndarray:
    """Decoded location per sample: the location of the winning unit."""
    Y = _check_Y(Y)
    m = np.asarray(mapping)
    if m.ndim != 1 or m.size != Y.shape[1] or not np.issubdtype(m.dtype, np.integer) \
            or (m.size and m.min() < 0):
        raise ValueError(f"mapping must give one location (an integer >= 0) per unit: "
                         f"{Y.shape[1]} units, got {m.dtype} {m.shape}")
    return m[np.argmax(Y, axis=1)]


def fit_centroid_decoder(Y: np.ndarray, labels: np.ndarray, n_locations: int) -> np.ndarray:
    """Each location's centroid: the mean output vector over the training samples taken there,
    shape (n_locations, units); a location the training data never visited has a NaN row.

    The population read-out of place cells (every unit's rate, not only the winner's), as a
    rate-map template decoder reads a recorded ensemble: only the centroids are learned from
    labels, the units themselves were learned without them."""
    lab = _check_labels(labels, n_locations)
    Y = _check_Y(Y, lab.size)
    sums = np.zeros((n_locations, Y.shape[1]))
    np.add.at(sums, lab, Y)
    count = np.bincount(lab, minlength=n_locations)
    with np.errstate(invalid="ignore", divide="ignore"):
        return sums / count[:, None]  # 0 / 0 = NaN: never visited


def decode_nearest_centroid(Y: np.ndarray, centroids: np.ndarray, *,
                            chunk: int = 4096) -> np.ndarray:
    """Decoded location per sample: the location whose centroid is nearest (Euclidean);
    locations with a NaN (or infinite) centroid are never chosen. ``chunk`` rows at a time,
    so memory stays at chunk × locations × units."""
    Y = _check_Y(Y)
    c = np.asarray(centroids, float)
    if c.ndim != 2 or c.shape[1] != Y.shape[1]:
        raise ValueError(f"centroids must be (locations, {Y.shape[1]}) for {Y.shape[1]} "
                         f"units, got shape {c.shape}")
    usable = np.all(np.isfinite(c), axis=1)
    if not usable.any():
        raise ValueError("no location has a centroid (the training data visited none)")
    idx = np.flatnonzero(usable)
    out = np.empty(len(Y), int)
    for a in range(0, len(Y), chunk):
        d = ((Y[a:a + chunk, None, :] - c[None, idx, :]) ** 2).sum(axis=2)
        out[a:a + chunk] = idx[np.argmin(d, axis=1)]
    return out


def decoding_accuracy(Y: np.ndarray, labels: np.ndarray, decoder: np.ndarray,
                      neighbors: np.ndarray | None = None) -> tuple[float, float]:
    """(exact, within-one-step) accuracy of a decoder on ``Y`` (e.g. test data). ``decoder``:
    a unit → location mapping (1-D, :func:`fit_winner_decoder`: the winning unit's location) or
    location centroids (2-D, :func:`fit_centroid_decoder`: the nearest centroid's location)."""
    nb = None if neighbors is None else np.asarray(neighbors)
    if nb is not None and (nb.ndim != 2 or nb.shape[0] != nb.shape[1] or nb.dtype != bool):
        raise ValueError(f"neighbors must be a square boolean matrix, got {nb.dtype} {nb.shape}")
    dec = np.asarray(decoder)
    n = nb.shape[0] if nb is not None else dec.shape[0] if dec.ndim == 2 else None
    lab = _check_labels(labels, n)
    Y = _check_Y(Y, lab.size)
    pred = decode_nearest_centroid(Y, dec) if dec.ndim == 2 else decode_locations(Y, dec)
    if nb is not None and pred.size and pred.max() >= nb.shape[0]:
        raise ValueError(f"the decoder names location {pred.max()}; neighbors covers "
                         f"{nb.shape[0]} locations")
    exact = float(np.mean(pred == lab)) if lab.size else float("nan")
    if nb is None:
        return exact, exact
    near = float(np.mean(nb[pred, lab])) if lab.size else float("nan")
    return exact, near


# ---------------------------------------------------------------------------- binary cells
def balanced_accuracy(pred: np.ndarray, truth: np.ndarray) -> float:
    """Mean of the true-positive and true-negative rates (0.5 = chance). ``pred`` and
    ``truth``: booleans (or integers 0 and 1)."""
    pred, truth = _binary("pred", pred), _binary("truth", truth)
    if pred.shape != truth.shape:
        raise ValueError(f"pred {pred.shape} and truth {truth.shape} differ in shape")
    pos, neg = truth.sum(), (~truth).sum()
    if pos == 0 or neg == 0:
        return float("nan")
    return 0.5 * (float((pred & truth).sum()) / pos + float((~pred & ~truth).sum()) / neg)


def _binary(name: str, value: np.ndarray) -> np.ndarray:
    """``value`` as a boolean array: booleans, or integers 0 and 1 (floats, negative and other
    labels are refused: casting them would turn them into classes silently)."""
    a = np.asarray(value)
    if a.dtype.kind == "b":
        return a
    if a.dtype.kind not in "iu" or (a.size and (a.min() < 0 or a.max() > 1)):
        raise ValueError(f"{name} must hold booleans (or integers 0 and 1), got dtype {a.dtype}"
                         + (f" with values {a.min()}..{a.max()}"
                            if a.size and a.dtype.kind in "iuf" else ""))
    return a.astype(bool)


@dataclass
class BinaryCell:
    """A unit read as a detector: ``polarity * (y[unit] - threshold) > 0`` means "inside"."""

    unit: int
    threshold: float
    polarity: int
    train_balanced_accuracy: float

    def predict(self, Y: np.ndarray) -> np.ndarray:
        Y = _check_Y(Y)
        return self.polarity * (Y[:, self.unit] - self.threshold) > 0


def _best_threshold(y: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """Threshold maximising balanced accuracy of ``y > thr`` for ``truth``."""
    order = np.argsort(y, kind="stable")
    ys, ts = y[order], truth[order]
    pos, neg = ts.sum(), (~ts).sum()
    # predicting positive for samples strictly above position i
    tn = np.concatenate([[0], np.cumsum(~ts)])        # negatives at or below the cut
    fn = np.concatenate([[0], np.cumsum(ts)])
    bacc = 0.5 * ((pos - fn) / pos + tn / neg)
    # only cut between distinct values
    valid = np.concatenate([[True], ys[1:] != ys[:-1], [True]])
    bacc = np.where(valid, bacc, -np.inf)
    i = int(np.argmax(bacc))
    lo = ys[i - 1] if i > 0 else ys[0] - 1.0
    hi = ys[i] if i < ys.size else ys[-1] + 1.0
    return 0.5 * (lo + hi), float(bacc[i])


def fit_binary_cell(Y: np.ndarray, truth: np.ndarray, mask: np.ndarray | None = None,
                    units: np.ndarray | None = None) -> BinaryCell:
    """Choose, on training data, the unit, threshold and sign that best detect ``truth``
    (balanced accuracy). ``mask`` restricts the samples used (e.g. rooms only, no corridor)."""
    Y = _check_Y(Y)
    truth = np.asarray(truth, bool)
    if truth.shape != (Y.shape[0],):
        raise ValueError(f"truth must have shape ({Y.shape[0]},), got {truth.shape}")
    m = np.ones(Y.shape[0], bool) if mask is None else np.asarray(mask, bool)
    Ym, tm = Y[m], truth[m]
    if tm.all() or not tm.any():
        raise ValueError("truth needs both classes among the selected training samples")
    best = None
    for j in (range(Y.shape[1]) if units is None else units):
        for pol in (1, -1):
            thr, bacc = _best_threshold(pol * Ym[:, j], tm)
            if best is None or bacc > best.train_balanced_accuracy:
                best = BinaryCell(int(j), pol * thr, pol, bacc)
    return best


# ---------------------------------------------------------------------------- kidnapping
def recovery_times(correct: np.ndarray, events: np.ndarray, *, hold: int = 5,
                   horizon: np.ndarray | int | None = None) -> np.ndarray:
    """Ticks from each event until the read-out is right again and stays right for ``hold``
    consecutive ticks. ``correct`` is a boolean series (T,); ``events`` tick indices. The search
    for event ``i`` stops at the next event (or ``horizon`` ticks later); if it never recovers,
    the result is NaN."""
    c = np.asarray(correct)
    if c.ndim != 1 or c.dtype != bool:
        raise ValueError(f"correct must be a 1-D boolean series, got {c.dtype} {c.shape}")
    correct, hold = c, check_int("hold", hold, lo=1)
    ev = np.asarray(events)
    T = correct.size
    if ev.ndim != 1 or (ev.size and (not np.issubdtype(ev.dtype, np.integer) or ev.min() < 0
                                      or ev.max() >= T or np.any(np.diff(ev) < 0))):
        raise ValueError(f"events must be sorted tick indices in [0, {T}), got {ev!r:.80}")
    if horizon is not None:
        h = np.atleast_1d(horizon)
        if h.ndim != 1 or not h.size or h.dtype == bool or \
                not np.issubdtype(h.dtype, np.integer) or h.min() < 0:
            raise ValueError(f"horizon must be a number of ticks >= 0, or one per event (the "
                             f"last repeated), got {horizon!r:.80}")
    out = np.full(ev.size, np.nan)
    for i, e in enumerate(ev):
        stop = ev[i + 1] if i + 1 < ev.size else T
        if horizon is not None:
            stop = min(stop, e + int(h[min(i, h.size - 1)]))
        for r in range(0, max(stop - e - hold + 1, 0)):
            if correct[e + r: e + r + hold].all():
                out[i] = r
                break
    return out

