"""Shared fixtures for the bvox Python tests. The package is imported from
the source tree (python/) and the library from $BVOX_LIBRARY, which CTest
sets to the build's libbvox.so.0."""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


# awkward sizes: nz = 1, 63, 64, 65, 130; odd nx, ny
SIZES = [(5, 3, 1), (7, 4, 63), (3, 5, 64), (6, 3, 65), (9, 7, 130)]


def random_mask(rng, shape, p=0.4):
    return rng.random(shape) < p
