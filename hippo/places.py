"""Place sources: what turns one tick's senses into place-cell activities for the brain.

- :class:`LearnedPlaceCells` — RC-SFA-ICA fitted on the robot's own sensor stream (the
  default everywhere), optionally read out by radial-basis prototypes.
- :class:`GroundTruthPlaceCells` — Gaussian fields on the true position; they exist only to
  measure what perception costs, and they are the one module that reads the ground truth
  (passed explicitly as ``truth``, never through the observation).
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from hippo._checks import check_finite, check_positive
from hippo.perception.prototypes import PlacePrototypes
from hippo.perception.relocate import SequenceRelocaliser
from hippo.types import GroundTruth, Observation

__all__ = ["GroundTruthPlaceCells", "LearnedPlaceCells", "PlaceSource"]


class PlaceSource(Protocol):
    """Anything that turns an observation into place-cell activities (``n_units`` of them)."""

    kind: str
    n_units: int

    def step(self, obs: Observation, truth: GroundTruth | None = None) -> np.ndarray: ...

    def reset(self) -> None: ...

    def prime(self, sensors: np.ndarray) -> None: ...

    # optional: ``lifted()``, called by the brain when the robot is picked up and put down


def _fitted_units(model: Any) -> int:
    """The number of outputs ``model`` was fitted with (its parameters may have been changed by
    ``set_params`` since, which changes no fitted part)."""
    std = getattr(model, "output_std_", None)
    return int(model.params.n_ica) if std is None else int(np.shape(std)[0])


class LearnedPlaceCells:
    """Place cells learned by RC-SFA-ICA from the robot's own distance sensors (the default).

    Wraps a fitted :class:`~hippo.perception.place_cells.RCSFAICA`; ``step`` feeds it the sensor
    readings only (never the pose or odometry). With ``prototypes`` (a fitted
    :class:`~hippo.perception.prototypes.PlacePrototypes`), the activities are those of
    radial-basis place cells over the whole ICA population vector instead of the ICA units
    themselves (less aliasing; see that module). With ``relocaliser`` (a fitted
    :class:`~hippo.perception.relocate.SequenceRelocaliser`), a lift (:meth:`lifted`) makes the
    reservoir jump to where the robot's next readings match its exploration.
    """

    kind = "learned"
    relocaliser: SequenceRelocaliser | None = None   # (snapshots saved before it existed)
    anchored = False   # the reservoir was re-anchored on this tick

    def __init__(self, model: Any, prototypes: PlacePrototypes | None = None, *,
                 relocaliser: SequenceRelocaliser | None = None) -> None:
        if getattr(model, "ica_", None) is None:
            raise ValueError("LearnedPlaceCells needs a fitted RCSFAICA model")
        if prototypes is not None:
            prototypes._check_fitted()
            d, n_ica = prototypes.centres_.shape[1], _fitted_units(model)
            if d != n_ica:
                raise ValueError(f"prototypes were fitted on {d}-dimensional outputs; the "
                                 f"model has n_ica={n_ica}")
        self.model = model
        self.prototypes = prototypes
        self.n_units = prototypes.n_units if prototypes is not None else _fitted_units(model)
        if relocaliser is not None and not isinstance(relocaliser, SequenceRelocaliser):
            raise TypeError(f"relocaliser must be a SequenceRelocaliser, got {relocaliser!r}")
        if relocaliser is not None and (model.params.downsample > 1 or model.params.slow_pool):
            raise ValueError("re-anchoring sets the reservoir state alone: it needs a model "
                             "without down-sampling or a slow pool")
        self.relocaliser = relocaliser

    def step(self, obs: Observation, truth: GroundTruth | None = None) -> np.ndarray:
        """Activities after this tick's sensor readings (``truth`` is ignored)."""
        rel = self.relocaliser
        self.anchored = False
        if rel is not None and rel.active:
            x = rel.observe(obs.ir, obs.moving)
            if x is not None:
                self.model.reservoir_.reset(x)   # re-anchored: this reading moves it on
                self.anchored = True
        y = self.model.step(obs.ir)
        # the model's output is finite and of the prototypes' dimension: no second check
        return y if self.prototypes is None else self.prototypes._step(y)

    def reset(self) -> None:
        self.model.reset_state()
        if self.relocaliser is not None:
            self.relocaliser.stop()

    def lifted(self) -> None:
        """The robot was picked up and put down: re-anchor the reservoir once its readings
        match a stretch of its exploration (nothing without a relocaliser)."""
        if self.relocaliser is not None:
            self.relocaliser.start()

    def prime(self, sensors: np.ndarray) -> None:
        """Start the online loop from the state of a robot that has been sensing: reset, then
        run the reservoir through recent readings ``sensors`` (T, n_inputs). A zero reservoir
        state is far from where the robot's inputs hold it, and the slow features amplify it:
        measured on the patrol course, the ICA outputs then stay off their training range (and
        every prototype silent) for about 100 s."""
        self.model.reset_state()
        for u in np.asarray(sensors, dtype=float):
            self.model.step(u)  # the prototypes hold no state: nothing else to run


class GroundTruthPlaceCells:
    """Gaussian place fields on the true position — only to measure what perception costs.

    ``a_k = exp(-|p - c_k|² / (2 σ²))`` with centres ``c_k`` (cm) and width ``sigma``. The
    position ``p`` comes from the ground truth handed to :meth:`step` (``World.truth``), which
    the brain passes on to this source only.
    """

    kind = "ground-truth"

    def __init__(self, centres: np.ndarray, sigma: float = 10.0) -> None:
        c = check_finite("centres", centres)
        if c.ndim != 2 or c.shape[1] != 2:
            raise ValueError(f"centres must be an (N, 2) array of (x, y) in cm, got shape "
                             f"{c.shape}")
        self.centres = c
        if len(self.centres) == 0:
            raise ValueError("GroundTruthPlaceCells needs at least one centre")
        self.sigma = check_positive("sigma", sigma)
        self.n_units = len(self.centres)

    def step(self, obs: Observation, truth: GroundTruth | Any | None = None) -> np.ndarray:
        """Activities at the true position ``truth.pose`` (``truth`` is required)."""
        if truth is None:
            raise ValueError("GroundTruthPlaceCells read the true position: pass truth="
                             "world.truth (a GroundTruth) to step(), e.g. agent.step(obs, "
                             "world.truth)")
        d2 = np.add.reduce((self.centres - np.asarray(truth.pose[:2])) ** 2, axis=1)  # np.sum
        return np.exp(-d2 / (2 * self.sigma**2))

    def reset(self) -> None:
        pass

    def prime(self, sensors: np.ndarray) -> None:
        """Nothing to prime: the fields read the true position."""
