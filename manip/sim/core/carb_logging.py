"""`carb`: the logging functions of Isaac Sim's Carbonite module, through Python logging.

An Isaac script's `import carb` becomes `from manip.sim import carb`; `carb.log_error(msg)`
and friends then go to the `logging` logger "manip.sim.carb" (configure it like any other
logger: `logging.basicConfig(level=logging.INFO)` shows `log_info` messages).

Levels: `log_verbose` -> DEBUG, `log_info` -> INFO, `log_warn` -> WARNING, `log_error` ->
ERROR, `log_fatal` -> CRITICAL. Unlike Carbonite, nothing else of `carb` (settings,
events, profiler) exists here.
"""

from __future__ import annotations

import logging
from types import SimpleNamespace

#: The logger of every `carb.log_*` message (its name is Isaac's module's, under manip.sim).
logger = logging.getLogger("manip.sim.carb")

__all__ = ["carb", "log_verbose", "log_info", "log_warn", "log_warning", "log_error", "log_fatal"]


def _log(level: int, msg: object) -> None:
    # stacklevel=3: the record names the script that called carb.log_*, not this module.
    logger.log(level, "%s", msg, stacklevel=3)


def log_verbose(msg: object) -> None:
    """Log `msg` at DEBUG level."""
    _log(logging.DEBUG, msg)


def log_info(msg: object) -> None:
    """Log `msg` at INFO level."""
    _log(logging.INFO, msg)


def log_warn(msg: object) -> None:
    """Log `msg` at WARNING level."""
    _log(logging.WARNING, msg)


log_warning = log_warn


def log_error(msg: object) -> None:
    """Log `msg` at ERROR level."""
    _log(logging.ERROR, msg)


def log_fatal(msg: object) -> None:
    """Log `msg` at CRITICAL level."""
    _log(logging.CRITICAL, msg)


#: Isaac's `carb` as one object (`from manip.sim import carb`): its logging functions.
carb = SimpleNamespace(log_verbose=log_verbose, log_info=log_info, log_warn=log_warn, log_warning=log_warning,
                       log_error=log_error, log_fatal=log_fatal)
