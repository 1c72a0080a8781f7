"""Flight conditions on a grid of stamps, interpolated in between: the per-message cache.

:class:`KnotGrid` evaluates the conditions exactly only at the knots ``j step`` (``step`` =
``conditions_step``) and interpolates linearly in between. The knots are fixed stamps, not set by
the messages, so a stamp and a state always get the same numbers whatever came before (live, or
replayed in any order). Interpolation error about (h v / L)^2 / 8 for knots h v metres apart and
fields varying over L: about 2e-9 of the density at 0.01 s, 2e-7 at 0.1 s; NRLMSISE-00's own
steps are spread over the interval that crosses them. docs/physics.md, section 5.4.
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
    """``(j, past)``: the knot ``j step`` at or before (or within :data:`KNOT_SNAP_S` of) a
    ``stamp`` [s], and ``stamp - j step`` [s] (0 on a knot), for a ``step`` [s] > 0."""
    j = math.floor(stamp / step)
    past = stamp - j * step
    if past >= step - KNOT_SNAP_S:
        return j + 1, 0.0
    if past <= KNOT_SNAP_S:
        return j, 0.0
    return j, past


class KnotGrid:
    """The flight conditions of one orbital state on the knots, interpolated in between.

    A cache keyed by the orbital state (compared with ``==``: another state forgets the knots),
    bounded by ``kept`` knots (the oldest goes first), counting :attr:`hits`, :attr:`misses`,
    :attr:`evaluations` and :attr:`prepared_used`. A stamp within :data:`KNOT_SNAP_S` of a knot
    takes its conditions; if a knot around a stamp cannot be evaluated (e.g. above the
    atmosphere model) the stamp is evaluated exactly. With ``step`` = 0 every stamp is its own
    knot.

    Parameters
    ----------
    step : float
        Knot spacing [s], >= 0.
    evaluate : callable
        ``evaluate(key, stamp)``: the exact :class:`FlightConditions` of the orbital state
        ``key`` at ``stamp`` [s]; raises ValueError if there are none.
    kept : int, optional
        Largest number of knots kept, >= 3.

    Raises
    ------
    ValueError
        For a step that is not a finite number >= 0 or fewer than 3 knots kept.
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
        """Evaluate with ``evaluate`` on knots ``step`` [s] apart from now on (the knots go, the
        counters stay); ValueError for a step not finite and >= 0 (nothing changed then)."""
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
        """The flight conditions of the orbital state ``key`` at ``stamp`` [s], UTC ``time``.

        Raises ValueError from ``evaluate`` at the stamp itself (e.g. an altitude outside the
        model).
        """
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
        """Evaluate ahead the knots a request at ``stamp`` will need; whether they are ready.

        With ``step`` > 0 the knots around the stamp and, if those were kept already, the knot
        :data:`KNOT_LOOKAHEAD` steps on (at most one evaluation per call in a regular stream).
        A later :meth:`conditions` at this stamp and key counts in :attr:`prepared_used`; its
        numbers are those it would have had without.
        """
        step = self.step
        try:
            if step > 0.0:
                misses = self.misses
                j, past = knot_position(stamp, step)
                self._knot(key, j)
                if past != 0.0:
                    self._knot(key, j + 1)
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
        """Knot ``index`` of ``key``, kept or evaluated (and kept, the oldest going first)."""
        if key is not self._key and key != self._key:  # (as containers compare)
            self._key = key
            self._knots = {}
        knots = self._knots
        knot = knots.get(index)
        if knot is not None:
            self.hits += 1
            return knot
        self.misses += 1
        step = self.step
        if step > 0.0:
            knot = KnotEnds(self.evaluate(key, index * step))
        else:  # nothing to interpolate
            knot = KnotEnds(self.evaluate(key, index))
        self.evaluations += 1
        if len(knots) >= self.kept:
            del knots[next(iter(knots))]
        knots[index] = knot
        return knot


def _at_time(conditions: FlightConditions, time: _dt.datetime) -> FlightConditions:
    """A knot's conditions at ``time`` (a knot serves the stamps within :data:`KNOT_SNAP_S`)."""
    if time == conditions.time:
        return conditions
    return dataclasses.replace(conditions, time=time)
