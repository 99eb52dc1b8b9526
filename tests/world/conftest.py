"""Shared fixtures of the world tests: small worlds generated once per session."""

import pytest

from sylva.world import World, WorldConfig


@pytest.fixture(scope="session")
def small_cfg():
    return WorldConfig(seed=11, chunk_size=16)


@pytest.fixture(scope="session")
def small_store(small_cfg, tmp_path_factory):
    """A 48 x 32 world (3 x 2 chunks of 16) generated in this process."""
    folder = tmp_path_factory.mktemp("world")
    store = World(small_cfg, size=(48, 32)).generate(folder, workers=1)
    yield store
    store.close()
