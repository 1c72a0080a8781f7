"""Flight conditions on a grid of stamps, interpolated in between: the per-message cache.

An attitude stream at 1 kHz asks for the flight conditions of one orbital state at every stamp;
an exact evaluation runs NRLMSISE-00, the Earth's orientation and the accommodation model.
:class:`KnotGrid` evaluates them exactly only at the *knots*, the stamps ``j step``
for integers j (``step`` = ``conditions_step``, 0.01 s by default), and interpolates linearly in
between (:mod:`adbsat_ros.environment.interpolation`). The knots are fixed stamps, not set by the
messages, so a stamp and a state always get the same numbers whatever came before (live, or
replayed from a bag in any order), and a stream stamped on multiples of the step lands on knots.

Interpolation error: for a first-order propagated state the positions are linear in time, so the
interpolated position is the propagated one (to rounding); the other fields are smooth along the
orbit and err by about (h v / L)^2 / 8 for knots h v metres apart and fields varying over L
(hundreds of km horizontally, tens of km vertically): about 2e-9 of the density at 0.01 s
(77 m at 7.7 km/s), 2e-7 at 0.1 s (checked in ``test/environment/test_knots.py``). NRLMSISE-00's
own steps (e.g. at exactly 300 km) are spread over the interval that crosses them.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
from typing import Callable

from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.interpolation import KnotEnds, mixed_conditions

#: A stamp this close to a knot [s] takes the knot's conditions alone: UNIX stamps as float
#: seconds resolve 2.4e-7 s, so a stream stamped on multiples of the step (e.g. 100 Hz at the
#: default 0.01 s) lands on knots and needs one evaluation per message, as without knots.
KNOT_SNAP_S = 1e-6
#: Knots kept (the grid's bound): the two around the latest stamp, the one after them (the
#: look-ahead of :meth:`KnotGrid.prepare`), one spare.
KNOTS_KEPT = 4
#: :meth:`KnotGrid.prepare` also evaluates the knot this many steps after the one at or before
#: the prepared stamp (when that stamp needed no new knot), so that the attitudes of the next
#: interval find its far knot ready.
KNOT_LOOKAHEAD = 2


def knot_position(stamp: float, step: float) -> tuple:
    """The knot at or before a stamp and the time past it.

    Parameters
    ----------
    stamp : float
        Message stamp [s].
    step : float
        Knot spacing [s], > 0.

    Returns
    -------
    j : int
        Index of the knot ``j step`` at or before ``stamp``, or of the knot within
        :data:`KNOT_SNAP_S` of it.
    past : float
        ``stamp - j step`` [s], in (KNOT_SNAP_S, step - KNOT_SNAP_S), or 0 for a stamp within
        KNOT_SNAP_S of knot j.
    """
    j = math.floor(stamp / step)
    past = stamp - j * step
    if past >= step - KNOT_SNAP_S:
        return j + 1, 0.0
    if past <= KNOT_SNAP_S:
        return j, 0.0
    return j, past


class KnotGrid:
    """The flight conditions of one orbital state on the knots, interpolated in between.

    A cache with one concern: its key is the orbital state the knots belong to (compared by
    value, ``==``: another state forgets the knots, the same one sent again keeps them), its bound
    ``kept`` knots (the oldest goes first), and it counts its lookups (:attr:`hits`,
    :attr:`misses`), the exact evaluations made (:attr:`evaluations`) and the requests at the
    stamp :meth:`prepare` made ready (:attr:`prepared_used`).

    With ``step`` > 0 the knots are the stamps ``j step``; a stamp within :data:`KNOT_SNAP_S` of
    a knot takes that knot's conditions, any other one is interpolated between the two knots
    around it, and if one of those cannot be evaluated (e.g. it lies above the atmosphere model
    while the stamp does not) the stamp itself is evaluated exactly. With ``step`` = 0 every
    stamp is its own knot: evaluated exactly, and kept for another request at that stamp.

    Parameters
    ----------
    step : float
        Knot spacing [s], >= 0.
    evaluate : callable
        ``evaluate(key, stamp)``: the exact :class:`FlightConditions` of the orbital state
        ``key`` at ``stamp`` [s]; raises ValueError if there are none (e.g. outside the
        atmosphere model).
    kept : int, optional
        Largest number of knots kept, >= 3 (the two around a stamp and the look-ahead).

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
        """Evaluate with ``evaluate`` on knots ``step`` apart from now on.

        The knots kept go (they were another evaluation's); the counters stay.

        Raises
        ------
        ValueError
            For a step that is not a finite number >= 0 (nothing changed then).
        """
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
        """The flight conditions of the orbital state ``key`` at ``stamp``.

        Parameters
        ----------
        key : object
            The orbital state (what ``evaluate`` takes; compared with ``==``).
        stamp : float
            Message stamp [s].
        time : datetime.datetime
            UTC of ``stamp`` (the time of the result).

        Raises
        ------
        ValueError
            From ``evaluate`` at the stamp itself (e.g. an altitude outside the model).
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
        """Evaluate ahead the knots a request at ``stamp`` will need.

        With ``step`` > 0: the knots around the stamp and, if they were kept already, the knot
        :data:`KNOT_LOOKAHEAD` steps on, so that at most one knot is evaluated per call in a
        regular stream, one interval before any stamp needs it. With ``step`` = 0: the exact
        conditions at the stamp. A later :meth:`conditions` at this stamp and key counts in
        :attr:`prepared_used`. The numbers of any request are those it would have had without.

        Returns
        -------
        bool
            Whether the stamp's knots are ready (False if one cannot be evaluated).
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
    """A knot's conditions at ``time`` (themselves at their own time; a knot's conditions serve
    the stamps within :data:`KNOT_SNAP_S` of it)."""
    if time == conditions.time:
        return conditions
    return dataclasses.replace(conditions, time=time)
