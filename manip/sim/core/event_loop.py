"""Kit's event loop, one frame at a time: coroutines a script schedules outside a running loop.

In Isaac Sim, scripts run inside Kit, whose asyncio loop turns once per app update, so
`asyncio.ensure_future(world.reset_async())` written at a script's top level runs at the
next frame. A plain Python script has no running loop: `ensure_future` then puts the task on
the thread's current event loop, which nobody runs, and the coroutine silently never
executes. `run_pending_coroutines()` (called by `World.step()` and `SimulationApp.update()`)
turns that loop once, as Kit's frame would: every task ready to run advances to its next
suspension point (the `*_async` methods of `manip.sim` complete without suspending, so a
chain of them finishes within one frame). Inside a running loop (Kit-style tests,
`asyncio.run(...)`) it does nothing: that loop runs the tasks itself.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import warnings

logger = logging.getLogger(__name__)


def _idle_current_loop() -> asyncio.AbstractEventLoop | None:
    """The main thread's current event loop if it is set and not running, else None."""
    if threading.current_thread() is not threading.main_thread():
        return None
    try:
        asyncio.get_running_loop()
        return None  # inside a running loop: it runs its tasks itself
    except RuntimeError:
        pass
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            loop = asyncio.get_event_loop_policy().get_event_loop()
        except RuntimeError:  # no current loop (e.g. after asyncio.run): nothing was scheduled on one
            return None
    if loop.is_closed() or loop.is_running():
        return None
    return loop


async def _one_frame() -> None:
    await asyncio.sleep(0)


def run_pending_coroutines() -> int:
    """Turn the thread's idle event loop once if tasks are pending on it (one Kit frame).

    Returns:
        The number of tasks that were pending before the turn (0: nothing was run).
    """
    loop = _idle_current_loop()
    if loop is None:
        return 0
    pending = [t for t in asyncio.all_tasks(loop) if not t.done()]
    if not pending:
        return 0
    logger.debug("running %d coroutine(s) scheduled outside a running event loop", len(pending))
    loop.run_until_complete(_one_frame())
    for task in pending:  # surface a failed coroutine as Kit's console would, not at garbage collection
        if task.done() and not task.cancelled() and task.exception() is not None:
            raise task.exception()
    return len(pending)
