"""The viser server every manip browser view runs on: z up, a ground grid, a robot-sized camera."""

from __future__ import annotations

import logging

import viser

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)

#: Default camera: position and look-at point [m] (base frame, z up).
CAMERA_POSITION = (1.3, 0.9, 0.8)
CAMERA_LOOK_AT = (0.3, 0.0, 0.35)


def start_server(host: str = "127.0.0.1", port: int = 8080, *, verbose: bool = True,
                 grid: bool = True) -> viser.ViserServer:
    """Start a viser server (it serves its web client from the installed package).

    Args:
        host: interface ("127.0.0.1": this machine only, reach it over SSH with
            `ssh -L PORT:localhost:PORT`; "0.0.0.0": every interface).
        port: TCP port; viser takes the next free one if it is in use
            (`server.get_port()` says which).
        verbose: let viser print the URL.
        grid: draw a 2 m ground grid at z = 0.

    Raises:
        InvalidInputError: `port` is not in 1..65535.
    """
    if isinstance(port, bool) or not isinstance(port, int) or not 0 < port < 65536:
        raise InvalidInputError(f"port must be an integer in 1..65535; got {port!r}")
    server = viser.ViserServer(host=host, port=port, verbose=verbose)
    server.scene.set_up_direction("+z")
    server.initial_camera.position = CAMERA_POSITION
    server.initial_camera.look_at = CAMERA_LOOK_AT
    if grid:
        server.scene.add_grid("/ground", width=2.0, height=2.0, cell_size=0.1, section_size=0.5)
    logger.info("viser serving on http://localhost:%d", server.get_port())
    return server
