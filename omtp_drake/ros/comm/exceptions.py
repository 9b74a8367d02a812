"""rospy's exceptions (``rospy.exceptions``): what a blocking call, a topic or a service raises."""

from __future__ import annotations


class ROSException(Exception):
    """rospy's base exception."""


class ROSInterruptException(ROSException, KeyboardInterrupt):
    """A blocking call was interrupted by shutdown."""


class ROSInitException(ROSException):
    pass


class ROSSerializationException(ROSException):
    pass


class ROSTimeMovedBackwardsException(ROSInterruptException):
    pass


class ServiceException(ROSException):
    """A service call failed (no such service, wrong type, or the service failed)."""
