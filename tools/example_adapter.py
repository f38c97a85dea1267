#!/usr/bin/env python3
"""An example adapter for the Specula driver protocol (docs/book/src/driver-protocol.md).

It answers the protocol on stdin/stdout for a *fake* device: four axes that go exactly where
they are told, a light source, and a 12-bit camera looking at a glossy grey sample (a
Gaussian highlight over a diffuse base), without noise. Replace the `FakeDevice` methods with
calls to your motion controller and camera; keep the rest.

    specula measure --connect "exec:python3 tools/example_adapter.py" \
        --calibration tools/example_adapter_calibration.toml --out fake.binary

(The fake camera has no noise, so it cannot be calibrated with `specula calibrate`, which
measures the noise; tools/example_adapter_calibration.toml is its calibration, written by
hand. It does not offer the optional `mount` method: it answers `unknown_method`, as any
adapter may, and `specula calibrate` then asks the operator to mount each target.)

Options (for testing Specula's handling of a misbehaving device):
    --token T          require this token in hello
    --die-after N      exit abruptly after answering N requests (a crashed adapter)

Only the Python standard library is used.
"""

import argparse
import json
import math
import sys

PROTOCOL = 1


class DeviceError(Exception):
    """An error the device reports: kind is one of the protocol's device kinds."""

    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind
        self.message = message


class FakeDevice:
    """A noise-free device. Angles in radians, times in seconds (see the protocol)."""

    WHITE_LEVEL = 4095.0
    BLACK_LEVEL = 64.0
    # Raw units per second for a radiance factor of 1 at full light.
    GAIN_DN_S = 2.0e5
    PIXELS = 1849
    LIMIT_RAD = math.radians(75.0)

    def __init__(self):
        self.axes = {"turntable_rad": 0.0, "camera_rad": 0.0,
                     "light_azimuth_rad": 0.0, "light_elevation_rad": math.radians(45.0)}
        self.level = 1.0

    def info(self):
        return {"model": "example adapter (fake glossy grey sample)", "serial": "example-1",
                "bit_depth": 12, "white_level": self.WHITE_LEVEL,
                "light_levels": [1.0, 0.1, 0.01], "exposure_range_s": [1e-5, 8.0]}

    def home(self):
        self.axes = {"turntable_rad": 0.0, "camera_rad": 0.0,
                     "light_azimuth_rad": 0.0, "light_elevation_rad": math.radians(45.0)}
        return dict(self.axes)

    def move_to(self, target):
        for name in ("camera_rad", "light_elevation_rad"):
            if abs(float(target[name])) > self.LIMIT_RAD + 1e-9:
                raise DeviceError("limit", f"{name} = {target[name]} rad is beyond 75 deg")
        self.axes = {k: float(target[k]) for k in self.axes}
        return dict(self.axes)

    def set_light(self, level):
        if not 0.0 <= level <= 1.0:
            raise DeviceError("limit", f"light level {level} is outside [0, 1]")
        self.level = level
        return {}

    def radiance_factor(self):
        """f_r cos(theta_i) of the fake sample for the current axes (lab frame; the sample
        is isotropic, so the turntable does not matter)."""
        a = self.axes["camera_rad"]
        p = self.axes["light_azimuth_rad"]
        t = self.axes["light_elevation_rad"]
        camera = (math.sin(a), 0.0, math.cos(a))
        light = (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))
        if light[2] <= 0.0 or camera[2] <= 0.0:
            return [0.0, 0.0, 0.0]
        h = [c + l for c, l in zip(camera, light)]
        norm = math.sqrt(sum(x * x for x in h))
        theta_h = math.acos(max(-1.0, min(1.0, h[2] / norm)))
        specular = 3.0 * math.exp(-(theta_h / 0.08) ** 2)
        base = [0.18 / math.pi, 0.20 / math.pi, 0.22 / math.pi]
        return [(b + specular) * light[2] for b in base]

    def capture(self, exposure_s, with_pixels):
        lo, hi = self.info()["exposure_range_s"]
        if not lo <= exposure_s <= hi:
            raise DeviceError("camera_fault", f"exposure {exposure_s} s is outside [{lo}, {hi}] s")
        raw = []
        saturated = []
        for value in self.radiance_factor():
            signal = self.BLACK_LEVEL + self.GAIN_DN_S * value * self.level * exposure_s
            raw.append(min(signal, self.WHITE_LEVEL))
            saturated.append(1.0 if signal >= self.WHITE_LEVEL else 0.0)
        pixels = [raw] * self.PIXELS if with_pixels else None
        return {"exposure_s": exposure_s, "light_level": self.level, "mean_raw": raw,
                "saturated_fraction": saturated, "pixel_count": self.PIXELS, "pixels": pixels}


def answer(device, request, token):
    """The reply to one request (a dict)."""
    rid = request.get("id")
    method = request.get("method")
    params = request.get("params") or {}
    try:
        if method == "hello":
            if params.get("protocol") != PROTOCOL:
                return {"id": rid, "error": {"kind": "version",
                                             "message": f"this adapter speaks protocol {PROTOCOL}"}}
            if token is not None and params.get("token") != token:
                return {"id": rid, "error": {"kind": "unauthorized", "message": "wrong token"}}
            result = {"protocol": PROTOCOL, "server": "example_adapter.py"}
        elif method == "info":
            result = device.info()
        elif method == "home":
            result = device.home()
        elif method == "move_to":
            result = device.move_to(params["target"])
        elif method == "set_light":
            result = device.set_light(float(params["level"]))
        elif method == "capture":
            result = device.capture(float(params["exposure_s"]), bool(params.get("with_pixels")))
        else:
            return {"id": rid, "error": {"kind": "unknown_method", "message": f"no method {method!r}"}}
    except DeviceError as e:
        return {"id": rid, "error": {"kind": e.kind, "message": e.message}}
    except (KeyError, TypeError, ValueError) as e:
        return {"id": rid, "error": {"kind": "bad_request", "message": f"bad params: {e!r}"}}
    return {"id": rid, "result": result}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--token", default=None)
    parser.add_argument("--die-after", type=int, default=None)
    args = parser.parse_args()
    device = FakeDevice()
    answered = 0
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
            reply = answer(device, request, args.token)
        sys.stdout.write(json.dumps(reply) + "\n")
        sys.stdout.flush()
        answered += 1
        if args.die_after is not None and answered >= args.die_after:
            print(f"example_adapter.py: dying after {answered} requests as asked", file=sys.stderr)
            sys.exit(3)


if __name__ == "__main__":
    try:
        main()
    except (BrokenPipeError, KeyboardInterrupt):
        # Specula closed the link (or the operator pressed Ctrl-C): nothing left to answer.
        sys.exit(0)
