#!/usr/bin/env python3
"""svbrdf's mean radiance against the reference's as the view tilts (docs/accuracy.md,
"Mean radiance against the view angle").

    bench/view_tilt.py SCENE.json [--tilts 40,44,...] [--precompute JSON] [--samples N] [--out DIR]

SCENE is a scene spec whose camera looks at the origin (a bench scene written by
`loom-lab sweep bench/sweep.json --emit-scenes DIR`). For each tilt the camera is
turned about the x axis to that many degrees from the +z normal, on the −y side, at
its distance from the origin; both methods render the view and the script prints the
reference's mean radiance per channel and svbrdf's mean over it. --precompute merges
settings (JSON, e.g. '{"view_directions": 36, "light_directions": 36}') into every
fabric's precompute. Fitted fabrics are cached in DIR/fabrics (default out/view-tilt);
LOOM_LAB names the loom-lab command (default build/lab/loom-lab of this checkout).
Needs oiiotool (Debian: openimageio-tools) for the image means.
"""

import argparse
import json
import math
import os
import shlex
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def mean_rgb(image):
    """The image's mean per channel, from oiiotool's statistics."""
    stats = subprocess.run(["oiiotool", "--stats", image], check=True, capture_output=True, text=True).stdout
    for line in stats.splitlines():
        if "Stats Avg:" in line:
            return [float(x) for x in line.split(":", 1)[1].split()[:3]]
    sys.exit(f"view_tilt: oiiotool printed no mean for {image}")


def tilted(scene, degrees, samples, precompute):
    """A copy of `scene` seen `degrees` off the normal at the same distance."""
    scene = json.loads(json.dumps(scene))
    camera = scene.setdefault("camera", {})
    position = camera.get("position", {})
    distance = math.sqrt(sum(position.get(axis, 0.0) ** 2 for axis in "xyz")) or 10.0
    angle = math.radians(degrees)
    camera["position"] = {"x": 0.0, "y": -distance * math.sin(angle), "z": distance * math.cos(angle)}
    camera["target"] = {}
    scene.setdefault("render", {})["reference_samples"] = samples
    for obj in scene.get("objects", []):
        if "fabric" in obj and precompute:
            obj["fabric"].setdefault("precompute", {}).update(precompute)
    return scene


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--tilts", default="40,44,48,52,56,60,64,68,72,76,80")
    parser.add_argument("--precompute", default="", help="precompute settings to merge, JSON")
    parser.add_argument("--samples", type=int, default=16, help="reference samples per pixel")
    parser.add_argument("--out", default="out/view-tilt")
    args = parser.parse_args()
    lab = shlex.split(os.environ.get("LOOM_LAB", os.path.join(HERE, "..", "build", "lab", "loom-lab")))
    precompute = json.loads(args.precompute) if args.precompute else {}
    with open(args.scene) as f:
        scene = json.load(f)
    os.makedirs(args.out, exist_ok=True)

    print("| tilt | reference mean (r, g, b) | svbrdf / reference (r, g, b) |")
    print("|---|---|---|")
    for degrees in (float(t) for t in args.tilts.split(",")):
        spec = os.path.join(args.out, f"tilt{degrees:g}.json")
        with open(spec, "w") as f:
            json.dump(tilted(scene, degrees, args.samples, precompute), f)
        means = {}
        for method in ("reference", "svbrdf"):
            image = os.path.join(args.out, f"tilt{degrees:g}_{method}.exr")
            subprocess.run(lab + ["render", spec, "--method", method, "--fabric-cache",
                                  os.path.join(args.out, "fabrics"), "--out", image],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            means[method] = mean_rgb(image)
        reference = means["reference"]
        ratios = [s / r if r > 0 else float("nan") for s, r in zip(means["svbrdf"], reference)]
        print(f"| {degrees:g}° | " + ", ".join(f"{r:.4f}" for r in reference) + " | " +
              ", ".join(f"{x:.3f}" for x in ratios) + " |", flush=True)


if __name__ == "__main__":
    main()
