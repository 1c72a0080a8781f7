"""adbsat_ros: ADBSat's free-molecular panel method as a Python library, CLI and ROS 2 node.

Installable with pip (``pip install .``, extras ``ros`` and ``test``) and buildable with colcon
as an ament_python package.
"""

from glob import glob

from setuptools import find_packages, setup

PACKAGE = "adbsat_ros"

ROS_JAZZY = [
    "ros-jazzy-rclpy>=7.1.5",
    "ros-jazzy-rmw-fastrtps-cpp>=8.4",
    "ros-jazzy-geometry-msgs>=5.3",
    "ros-jazzy-nav-msgs>=5.3",
    "ros-jazzy-std-msgs>=5.3",
    "ros-jazzy-diagnostic-msgs>=5.3",
]

setup(
    name=PACKAGE,
    version="0.1.0",
    description="Free-molecular satellite aerodynamics (ADBSat's panel method) for Python and ROS 2",
    long_description=open("README.md", encoding="utf-8").read(),
    long_description_content_type="text/markdown",
    license="Apache-2.0",
    python_requires=">=3.10",
    packages=find_packages(exclude=["test", "test.*", "bench"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", glob("config/*.yaml") + glob("config/*.xml")),
    ],
    install_requires=[
        "numpy>=1.26",
        "scipy>=1.11",
        "trimesh>=4.0",
        "embreex>=2.17.7; platform_machine=='x86_64'",
        "nrlmsise00>=0.1.2",
        "pyerfa>=2.0.1",
        "rosbags>=0.10",
        "matplotlib>=3.8",
        "tqdm>=4.66",
    ],
    extras_require={
        "ros": ROS_JAZZY,
        "test": ["pytest>=8.0", "hypothesis>=6.100"],
    },
    zip_safe=True,
    maintainer="adbsat_ros developers",
    maintainer_email="dev@adbsat-ros.invalid",
    entry_points={
        "console_scripts": [
            "adbsat-ros = adbsat_ros.cli:main",
            "adbsat_node = adbsat_ros.ros.node:main",
            "adbsat_orbit_publisher = adbsat_ros.ros.orbit_publisher:main",
        ],
    },
)
