"""Shared set-up of the Python module's tests: paths from CTest's environment, the content cache in
the run's own temporary folder (never the user's)."""
import os
import tempfile

import pytest

SHARED = os.environ.get("AQ_SHARED", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared"))
SOURCE = os.environ.get("AQ_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("AQ_BIN", os.path.join(SOURCE, "build", "app", "aquarelle"))
BOTTLE = os.path.join(SHARED, "assets/gltf/WaterBottle/glTF/WaterBottle.gltf")
BUSH = os.path.join(SHARED, "assets/plants/ez-tree/ez_bush2.glb")
OAK = os.path.join(SOURCE, "scenes/data/oak.json")


@pytest.fixture(scope="session", autouse=True)
def own_cache(tmp_path_factory):
    os.environ["AQUARELLE_CACHE_DIR"] = str(tmp_path_factory.mktemp("cache"))
    yield
