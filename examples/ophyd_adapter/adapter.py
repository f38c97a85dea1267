#!/usr/bin/env python3
"""A Specula driver-protocol adapter on ophyd, the device layer of the Bluesky lab-control
stack (https://blueskyproject.io), with its simulated motors and detector.

The goniometer's four axes are ophyd positioners, the light level an ophyd signal and the
camera an ophyd detector that is triggered and read for every capture; here they are
ophyd's simulators (`ophyd.sim.SynAxis`, `ophyd.sim.SynSignal`), looking at the same fake
glossy grey sample as tools/example_adapter.py. On a real goniometer, replace `make_axes`,
`make_light` and `make_camera` with your EPICS motors (`ophyd.EpicsMotor`), your light
controller and your area detector; the protocol (tools/example_adapter.py's `answer`) stays.

    pip install ophyd
    specula measure --connect "exec:python3 examples/ophyd_adapter/adapter.py" \\
        --calibration tools/example_adapter_calibration.toml --out ophyd.binary

The simulated camera has no noise, so the calibration is the example adapter's, written by
hand (see docs/book/src/own-goniometer.md for calibrating a real one with
`specula calibrate --connect`).
"""

import json
import math
import os
import sys

from ophyd import Signal
from ophyd.sim import SynAxis, SynSignal

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from example_adapter import FakeDevice, answer  # noqa: E402  (the protocol, one home)

MOVE_TIMEOUT_S = 30.0
AXES = ("turntable_rad", "camera_rad", "light_azimuth_rad", "light_elevation_rad")


def make_axes():
    """The goniometer's positioners, by the protocol's axis names (radians)."""
    return {name: SynAxis(name=name) for name in AXES}


def make_light():
    """The light source's level, 0 to 1."""
    return Signal(name="light_level", value=1.0)


def make_camera(scene):
    """The camera: a detector whose reading is the scene's radiance factor per channel."""
    return SynSignal(func=scene, name="camera")


class OphydDevice(FakeDevice):
    """FakeDevice's sample seen through ophyd: every move, light change and capture goes
    through an ophyd positioner, signal or detector."""

    def __init__(self):
        self.motors = make_axes()
        self.light = make_light()
        self.camera = make_camera(lambda: FakeDevice.radiance_factor(self))
        super().__init__()

    @property
    def axes(self):
        return {name: float(motor.readback.get()) for name, motor in self.motors.items()}

    @axes.setter
    def axes(self, target):
        statuses = [self.motors[name].set(float(value)) for name, value in target.items()]
        for status in statuses:
            status.wait(timeout=MOVE_TIMEOUT_S)

    @property
    def level(self):
        return float(self.light.get())

    @level.setter
    def level(self, value):
        self.light.put(float(value))

    def info(self):
        info = super().info()
        info["model"] = "ophyd simulated goniometer (fake glossy grey sample)"
        info["serial"] = "ophyd-sim-1"
        return info

    def radiance_factor(self):
        self.camera.trigger().wait(timeout=MOVE_TIMEOUT_S)
        return list(self.camera.read()["camera"]["value"])


def main():
    device = OphydDevice()
    for line in sys.stdin:
        if not line.strip():
            continue
        try:
            request = json.loads(line)
            if not isinstance(request, dict):
                raise ValueError("not an object")
        except ValueError as e:
            reply = {"id": None, "error": {"kind": "bad_request", "message": f"not JSON: {e}"}}
        else:
            reply = answer(device, request, None)
        if reply.get("result", {}).get("server") == "example_adapter.py":
            reply["result"]["server"] = "examples/ophyd_adapter/adapter.py"
        sys.stdout.write(json.dumps(reply) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    try:
        main()
    except (BrokenPipeError, KeyboardInterrupt):
        sys.exit(0)
