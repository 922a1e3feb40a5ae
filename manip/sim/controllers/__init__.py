"""Controllers: the implicit PD drives (`ArticulationController`), `BaseController` and the wheeled robots' (`base_controller`), `PickPlaceController`, `RMPFlowController` (a QP controller)."""
