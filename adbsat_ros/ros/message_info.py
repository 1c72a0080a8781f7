"""Messages lost on the way to the node, from each message's ``publication_sequence_number``
(filled by rmw_fastrtps) and the middleware's lost-message events.
"""

from __future__ import annotations

import inspect

from rclpy.event_handler import SubscriptionEventCallbacks

from adbsat_ros.estimator.health import SequenceGaps

#: The signature rclpy reads to pass a callback the message info too.
_WITH_INFO = inspect.Signature(
    [
        inspect.Parameter("message", inspect.Parameter.POSITIONAL_ONLY),
        inspect.Parameter("info", inspect.Parameter.POSITIONAL_ONLY),
    ]
)


class LostMessages:
    """The messages one subscription lost; subscribe with :meth:`callback` and
    :meth:`event_callbacks`, then :meth:`attach` it; ``gaps`` (SequenceGaps) counts them.
    """

    def __init__(self):
        self.gaps = SequenceGaps()
        self._subscription = None

    @property
    def lost(self) -> int:
        """Messages the subscription lost so far (:attr:`SequenceGaps.lost`)."""
        return self.gaps.lost

    def attach(self, subscription) -> None:
        """The subscription made with this counter (asked for its publisher count)."""
        self._subscription = subscription

    def callback(self, on_message) -> _CountingCallback:
        """A callback counting the message's number, then calling ``on_message(message)``."""
        return _CountingCallback(on_message, self)

    def event_callbacks(self) -> SubscriptionEventCallbacks:
        """The middleware's lost-message reports and publisher (un)matching, for the counts."""
        return SubscriptionEventCallbacks(message_lost=self._on_lost, matched=self._on_matched)

    def taken(self, info) -> None:
        """A message with ``info`` (rclpy's message info dict) was taken."""
        sequence = info.get("publication_sequence_number")
        if sequence is not None:  # (an RMW that does not number its messages: events only)
            self.gaps.number(sequence, self._single_publisher)

    def _single_publisher(self) -> bool:
        subscription = self._subscription
        return subscription is not None and subscription.get_publisher_count() == 1

    def _on_lost(self, status) -> None:
        self.gaps.reported(status.total_count_change)

    def _on_matched(self, status) -> None:
        if status.current_count_change:
            self.gaps.restart()


class _CountingCallback:
    """A callback taking the message and its info (by ``__signature__``): the SingleThreadedExecutor
    passes two arguments, the Jazzy EventsExecutor one tuple.
    """

    __signature__ = _WITH_INFO

    def __init__(self, on_message, lost: LostMessages):
        self._on_message = on_message
        self._lost = lost

    def __call__(self, *args) -> None:
        message, info = args if len(args) == 2 else args[0]
        self._lost.taken(info)
        self._on_message(message)
