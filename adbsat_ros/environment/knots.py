"""Flight conditions exact on fixed knots ``j step``, interpolated in between (:class:`KnotGrid`).

Fixed knots give a stamp the same numbers whatever came before. docs/physics.md, section 5.4.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
from typing import Callable

from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.interpolation import KnotEnds, mixed_conditions

#: A stamp this close to a knot [s] takes the knot's conditions alone (float UNIX stamps
#: resolve 2.4e-7 s), so a stream stamped on multiples of the step lands on knots.
KNOT_SNAP_S = 1e-6
#: Knots kept: the two around the latest stamp, the look-ahead of :meth:`KnotGrid.prepare`, a spare.
KNOTS_KEPT = 4
#: :meth:`KnotGrid.prepare` also evaluates the knot this many steps on (when the prepared stamp
#: needed no new knot), so the next interval finds its far knot ready.
KNOT_LOOKAHEAD = 2


def knot_position(stamp: float, step: float) -> tuple:
    """``(j, stamp - j step)`` of the knot at or before ``stamp`` [s] (snapped: 0 on a knot)."""
    j = math.floor(stamp / step)
    past = stamp - j * step
    if past >= step - KNOT_SNAP_S:
        return j + 1, 0.0
    if past <= KNOT_SNAP_S:
        return j, 0.0
    return j, past


class KnotGrid:
    """The per-message cache of one orbital state's conditions, on knots ``step`` [s] >= 0 apart.

    ``evaluate(key, stamp)``: the exact FlightConditions (ValueError if none; then the stamp is
    evaluated exactly); at most ``kept`` >= 3 knots; ``step`` 0: every stamp a knot.
    ValueError: a step not finite and >= 0, or fewer than 3 knots kept.
    """

    def __init__(
        self,
        step: float,
        evaluate: Callable[[object, float], FlightConditions],
        kept: int = KNOTS_KEPT,
    ):
        if int(kept) != kept or kept < 3:
            raise ValueError(f"kept must be an integer >= 3, got {kept!r}")
        self.kept = int(kept)
        self.hits = 0
        self.misses = 0
        self.evaluations = 0
        self.prepared_used = 0
        self.configure(step, evaluate)

    def configure(self, step: float, evaluate: Callable[[object, float], FlightConditions]):
        """New ``step`` [s] and ``evaluate``: the knots go, the counters stay."""
        step = float(step)
        if not (math.isfinite(step) and step >= 0.0):
            raise ValueError(f"step must be a finite number of seconds >= 0, got {step!r}")
        self.step = step
        self.evaluate = evaluate
        self.clear()

    @property
    def key(self):
        """The orbital state the kept knots belong to (None before the first)."""
        return self._key

    @property
    def knot_stamps(self) -> tuple:
        """The stamps [s] of the knots kept, oldest first."""
        if self.step > 0.0:
            return tuple(j * self.step for j in self._knots)
        return tuple(self._knots)

    def __len__(self) -> int:
        return len(self._knots)

    def clear(self) -> None:
        """Forget the knots and the prepared stamp (the counters stay)."""
        self._key = None
        self._knots: dict = {}  # knot index (j, or the stamp with step 0) -> KnotEnds
        self._prepared: tuple | None = None  # (key, stamp) of the latest prepare()

    def conditions(self, key, stamp: float, time: _dt.datetime) -> FlightConditions:
        """The conditions of ``key`` at ``stamp`` [s], UTC ``time``; ValueError of ``evaluate``."""
        prepared = self._prepared
        if (
            prepared is not None
            and prepared[1] == stamp
            and (prepared[0] is key or prepared[0] == key)
        ):
            self.prepared_used += 1
        step = self.step
        if step <= 0.0:  # every stamp its own knot
            return _at_time(self._knot(key, stamp).conditions, time)
        j, past = knot_position(stamp, step)
        try:
            a = self._knot(key, j)
            b = a if past == 0.0 else self._knot(key, j + 1)
        except ValueError:  # a knot outside the model's range: the stamp itself, exactly
            conditions = self.evaluate(key, stamp)
            self.evaluations += 1
            return conditions
        if past == 0.0:
            return _at_time(a.conditions, time)
        return mixed_conditions(a, b, past / step, time)

    def prepare(self, key, stamp: float) -> bool:
        """Evaluate ahead the knots ``stamp`` needs; whether ready. Changes no number."""
        step = self.step
        try:
            if step > 0.0:
                misses = self.misses
                j, past = knot_position(stamp, step)
                knot = self._knot(key, j)
                if past != 0.0:  # (both ready to mix)
                    _ = knot.mixing, self._knot(key, j + 1).mixing
                if self.misses == misses:
                    try:
                        self._knot(key, j + KNOT_LOOKAHEAD)
                    except ValueError:  # (e.g. above the atmosphere model: the stamp is not)
                        pass
            else:
                self._knot(key, stamp)
        except ValueError:
            return False
        self._prepared = (key, stamp)
        return True

    def _knot(self, key, index) -> KnotEnds:
        """Knot ``index`` of ``key``, kept or evaluated and kept."""
        if key is not self._key and key != self._key:  # (as containers compare)
            self._key = key
            self._knots = {}
        knots = self._knots
        knot = knots.get(index)
        if knot is not None:
            self.hits += 1
            return knot
        self.misses += 1
        step = self.step  # (0: nothing to interpolate, the index is the stamp)
        knot = KnotEnds(self.evaluate(key, index * step if step > 0.0 else index))
        self.evaluations += 1
        if len(knots) >= self.kept:
            del knots[next(iter(knots))]
        knots[index] = knot
        return knot


def _at_time(conditions: FlightConditions, time: _dt.datetime) -> FlightConditions:
    """A knot's conditions at ``time``."""
    if time == conditions.time:
        return conditions
    return dataclasses.replace(conditions, time=time)
