"""The ray backends as a fixture: every ray case runs with numpy and with Embree.

embreex is a dependency: only a developer machine without it may skip the Embree cases; in CI
(the CI variable set) a missing Embree fails them.
"""

import os

import pytest

from adbsat_ros.shading.rays import EMBREE_ERROR, has_embree

needs_embree = pytest.mark.skipif(
    not has_embree and not os.environ.get("CI"), reason=f"embreex not available ({EMBREE_ERROR})"
)


@pytest.fixture(params=["numpy", pytest.param("embree", marks=needs_embree)])
def backend(request):
    """Name of a ray backend."""
    return request.param
