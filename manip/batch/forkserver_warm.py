"""Imported by the fork server of the local backend (`process_pool.FORKSERVER_PRELOAD`) only.

Importing this module warms up a franka generator in the importing process
(`worker.warm_up`: about 0.7 s of CPU, most of it numba loading its cached kernels), so that
the workers the fork server forks inherit the loaded kernels and start in about 0.1 s. The
kernels do not depend on the robot; a worker still builds and warms the generators of its
batch's robots. Nothing else imports it: importing `manip` or `manip.batch` does no work.
"""

from __future__ import annotations

import logging

from manip.batch import worker

log = logging.getLogger(__name__)

#: The robot warmed in the fork server.
ROBOT = "franka"

try:
    worker.warm_up((ROBOT,))
except Exception:  # noqa: BLE001 - the server must live on: each worker then warms up itself
    log.warning("fork server warm-up failed; workers will load the kernels themselves", exc_info=True)
