"""config/fastdds_localhost.xml: two processes that use it find each other and talk, and every UDP
socket Fast DDS opens in them is bound to 127.0.0.1 (the profile replaces rmw_fastrtps's
LOCALHOST set-up, so it must keep discovery off the network itself; rmw_fastrtps's own set-up
binds to 0.0.0.0, so a profile Fast DDS ignored would fail here)."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import json
import os
import subprocess
import sys
from pathlib import Path

from ros_harness import HANG_TIMEOUT

PROFILE = Path(__file__).resolve().parents[2] / "config" / "fastdds_localhost.xml"

# A child process: "listen" subscribes to chatter and reports what it got (waiting at most
# argv[2] seconds for the first message) and its UDP sockets; "talk" publishes on chatter until
# killed.
CHILD = r'''
import json, os, socket, sys, time
import rclpy
from std_msgs.msg import String

def udp_sockets():
    """(address, port) of every UDP socket this process holds, from /proc."""
    inodes = set()
    for fd in os.listdir("/proc/self/fd"):
        try:
            link = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if link.startswith("socket:["):
            inodes.add(link[8:-1])
    found = []
    for table in ("/proc/self/net/udp", "/proc/self/net/udp6"):
        try:
            rows = open(table).read().splitlines()[1:]
        except FileNotFoundError:
            continue
        for row in rows:
            fields = row.split()
            if fields[9] in inodes:
                address, port = fields[1].split(":")
                if len(address) == 8:
                    address = socket.inet_ntoa(bytes.fromhex(address)[::-1])
                else:
                    address = "ipv6:" + address
                found.append([address, int(port, 16)])
    return found

rclpy.init()
node = rclpy.create_node("profile_" + sys.argv[1])
if sys.argv[1] == "listen":
    got = []
    node.create_subscription(String, "chatter", lambda m: got.append(m.data), 10)
    deadline = time.monotonic() + float(sys.argv[2])
    while not got and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    print(json.dumps({"received": len(got), "udp": udp_sockets()}), flush=True)
else:
    pub = node.create_publisher(String, "chatter", 10)
    while True:
        pub.publish(String(data="hello"))
        time.sleep(0.05)
'''


def test_profile_discovers_over_loopback_only():
    env = dict(
        os.environ,
        ROS_AUTOMATIC_DISCOVERY_RANGE="SYSTEM_DEFAULT",
        FASTRTPS_DEFAULT_PROFILES_FILE=str(PROFILE),
    )
    talker = subprocess.Popen(
        [sys.executable, "-c", CHILD, "talk"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        listener = subprocess.run(
            [sys.executable, "-c", CHILD, "listen", str(HANG_TIMEOUT)],
            env=env,
            capture_output=True,
            text=True,
            timeout=2 * HANG_TIMEOUT,
        )
    finally:
        talker.kill()
        talker.wait()
    assert listener.returncode == 0, listener.stderr
    report = json.loads(listener.stdout.strip().splitlines()[-1])
    assert report["received"] >= 1, "the two processes did not find each other through the profile"
    assert report["udp"], "no UDP socket found: the profile's UDP transport is missing"
    assert all(address == "127.0.0.1" for address, _ in report["udp"]), report["udp"]
