"""What the leak sweeps of bench/ share: writing a scene they built
quietly, and reading an image's mean."""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
from make_scenes import write_gltf_file  # noqa: E402


def write_quietly(path, doc, blob):
    """write_gltf_file without its report on stdout (the sweeps print JSON there)."""
    with open(os.devnull, "w") as quiet:
        saved, sys.stdout = sys.stdout, quiet
        try:
            write_gltf_file(path, doc, blob)
        finally:
            sys.stdout = saved


def image_mean(build, exr):
    """The image's mean (r, g, b), as build/lvcl-compare reports it."""
    out = subprocess.run([os.path.join(build, "lvcl-compare"), exr, exr], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out.splitlines()[0])["mean"]
