"""The timing half of a control tick, built in one place: winner -> batteries -> transition
cells -> non-occurrence.

:class:`TimingChain` owns one :class:`~hippo.timing.spectral.SpectralTiming`, the
:class:`~hippo.timing.transitions.TransitionCells` that read its batteries and the
:class:`~hippo.timing.non_occurrence.NonOccurrence` neurons that watch their predictions. Each
:meth:`TimingChain.step` is, in order::

    battery  = spectral.step(winner, dt)     # the new winner's battery restarts at 0
    readouts = cells.step(battery, dt)       # learn (a, b) with its delay; predict out of b
    omitted  = nonocc.step(readouts, dt)     # predicted events that are overdue

The brain (:class:`hippo.brain.Brain`) and the symbolic trials (:mod:`hippo.timing.trials`)
both step this object, so the chain's wiring has one home.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass

from hippo.timing.non_occurrence import NonOccurrence, NonOccurrenceParams
from hippo.timing.spectral import BatteryState, SpectralParams, SpectralTiming
from hippo.timing.transition_params import TransitionParams, TransitionReadout
from hippo.timing.transitions import TransitionCells

__all__ = ["TimingChain", "TimingStep"]


@dataclass(frozen=True, eq=False, init=False)
class TimingStep:
    """One tick of the chain: the active battery, the readouts of the transitions out of the
    winner (``{(a, b): TransitionReadout}``) and the keys whose non-occurrence neuron fired."""

    battery: BatteryState
    readouts: dict[tuple[int, int], TransitionReadout]
    omitted: list[Hashable]

    def __init__(self, battery: BatteryState, readouts: dict[tuple[int, int], TransitionReadout],
                 omitted: list[Hashable]) -> None:
        # one a tick: the fields written straight into the instance's dict
        d = self.__dict__
        d["battery"], d["readouts"], d["omitted"] = battery, readouts, omitted


class TimingChain:
    """Spectral timing, transition cells and non-occurrence, wired once (see module doc)."""

    def __init__(self, spectral: SpectralParams | None = None,
                 transitions: TransitionParams | None = None,
                 non_occurrence: NonOccurrenceParams | None = None) -> None:
        self.spectral = SpectralTiming(spectral)
        self.cells = TransitionCells(self.spectral, transitions)
        self.nonocc: NonOccurrence | None = NonOccurrence(non_occurrence)

    @classmethod
    def of(cls, spectral: SpectralTiming, cells: TransitionCells,
           nonocc: NonOccurrence | None = None) -> TimingChain:
        """The chain over existing modules (``cells`` must read ``spectral``'s batteries);
        without ``nonocc`` nothing watches the predictions (``omitted`` is always empty)."""
        if cells.timing is not spectral:
            raise ValueError("cells must read the batteries of spectral "
                             "(TransitionCells(spectral, ...))")
        chain = cls.__new__(cls)
        chain.spectral, chain.cells, chain.nonocc = spectral, cells, nonocc
        return chain

    def step(self, winner: int, dt: float, *, learn_event: bool = True) -> TimingStep:
        """Advance the chain by ``dt`` with ``winner`` the current state (learning never
        stops; ``learn_event=False``: a change of winner this tick teaches no delay, see
        :meth:`TransitionCells.step`)."""
        battery = self.spectral.step(winner, dt)
        readouts = self.cells.step(battery, dt, learn_event=learn_event)
        omitted = self.nonocc.step(readouts, dt) if self.nonocc is not None else []
        return TimingStep(battery, readouts, omitted)

    @property
    def state(self) -> int | None:
        """The current winner (None before the first step)."""
        return self.spectral.state
