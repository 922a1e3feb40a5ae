"""Fixtures of the batch tests: a Ray test cluster (module scope: one per test file)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def ray_cluster():
    """Ray's test cluster: two nodes of one CPU each, on this machine."""
    ray = pytest.importorskip("ray", reason="the Ray backend needs the ray extra: pip install 'manip-robotics[ray]'")
    from ray.cluster_utils import Cluster

    cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    cluster.add_node(num_cpus=1)
    ray.init(address=cluster.address, log_to_driver=False)
    yield ray
    from manip.batch import release_ray_actors

    release_ray_actors()
    ray.shutdown()
    cluster.shutdown()
