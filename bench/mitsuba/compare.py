"""fpgfx against Mitsuba 3 on one scene, side by side in one run.

`cargo xtask mitsuba` runs this in its own venv (target/mitsuba-env) with Mitsuba from
PyPI; docs/bench.md gives the figures and how to read them. It

1. translates an fpgfx scene file (TOML) into a Mitsuba scene: the same shapes, camera,
   point lights and Lambertian materials, the `direct` integrator with one emitter sample
   and no BSDF sample (one shadow ray per hit and light, as fpgfx traces), 1 spp;
2. times Mitsuba's render call (`mi.render` until the image is evaluated) in the
   `llvm_ad_rgb` variant (a vectorising JIT on every core) and in `scalar_rgb`, after one
   untimed call that compiles and caches the kernels;
3. times the whole `fpgfx render SCENE -o PNG` process (start-up, scene, render on the
   built-in target, read-back over its link, PNG), best of the runs;
4. checks that the two renderers drew the same picture (both frames as ⌊255·clamp(c)⌋:
   no pixel away from an edge may differ by more than 8 levels; the PSNR is printed): a
   wrong translation would make the speed figures meaningless, so it fails the run;
5. prints a table and the ratios.

Only what both renderers compute alike is accepted: Lambert materials without ambient,
reflection, texture or spot light, and a black background; anything else is refused with
the key that holds it. Mitsuba samples a random position inside each pixel while fpgfx
traces the pixel's centre, so edge pixels differ; the check skips them.
"""

import argparse
import json
import math
import statistics
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

# At most this share of the pixels may differ by more than 8 levels away from edges
# ([`off_edge_mismatches`]). The Lambert scene's frames have none; its cube turned the other
# way in the translation gives 13 612 (0.66 %), a field of view 5 % too wide far more,
# while the PSNR only drops from 50.6 to 45.3 and 33.4 dB: PSNR alone cannot tell.
MAX_OFF_EDGE = 0.0005
# How large a plane is drawn in Mitsuba (it has no unbounded plane): far beyond any
# camera's view in a scene of a few units.
PLANE_HALF_SIDE = 200.0


class SceneError(Exception):
    """The scene asks for something the comparison cannot give both renderers alike."""


def rotation(deg):
    """R = Rz·Ry·Rx in degrees: the order and signs of fpgfx's scene format."""
    ax, ay, az = (math.radians(v) for v in deg)
    sx, cx = math.sin(ax), math.cos(ax)
    sy, cy = math.sin(ay), math.cos(ay)
    sz, cz = math.sin(az), math.cos(az)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def object_matrix(obj):
    """The object's 4×4 M = T·R·S, as fpgfx builds it."""
    m = np.eye(4)
    r = rotation(obj.get("rotate", [0.0, 0.0, 0.0]))
    s = np.diag(obj.get("scale", [1.0, 1.0, 1.0]))
    m[:3, :3] = r @ s
    m[:3, 3] = obj.get("translate", [0.0, 0.0, 0.0])
    return m


def refuse_unless(cond, where, what):
    if not cond:
        raise SceneError(f"{where}: {what}")


def bsdf(name, mat):
    """A two-sided diffuse BSDF with reflectance k·colour (fpgfx shades both sides)."""
    where = f"material.{name}"
    for key in ("ambient", "specular", "reflection", "texture"):
        refuse_unless(key not in mat, f"{where}.{key}", "only Lambert materials compare")
    d = mat.get("diffuse")
    refuse_unless(d is not None, f"{where}.diffuse", "missing")
    refuse_unless(
        d.get("model", "lambert") == "lambert", f"{where}.diffuse.model", "only lambert"
    )
    k = d.get("k", 1.0)
    rho = [k * c for c in d.get("color", [1.0, 1.0, 1.0])]
    return {
        "type": "twosided",
        "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rho}},
    }


def shape(mi, i, obj, bsdfs):
    """One object as a Mitsuba shape with the same world-space surface."""
    where = f"object[{i}]"
    kind = obj["shape"]
    m = object_matrix(obj)
    sc = obj.get("scale", [1.0, 1.0, 1.0])
    mat = obj.get("material")
    refuse_unless(mat in bsdfs, f"{where}.material", f"no material {mat!r}")
    out = {"bsdf": {"type": "ref", "id": mat}}

    def point(p):
        return list(map(float, (m @ np.array([*p, 1.0]))[:3]))

    if kind == "sphere":
        # Mitsuba's sphere takes no non-uniform scale: centre and radius instead.
        refuse_unless(
            sc[0] == sc[1] == sc[2], f"{where}.scale", "a sphere must scale uniformly"
        )
        out |= {"type": "sphere", "center": point([0, 0, 0]), "radius": abs(sc[0])}
    elif kind == "cylinder":
        # Open, x² + z² = 1, y ∈ [−1, 1] in object space; Mitsuba's is open too.
        refuse_unless(
            sc[0] == sc[2], f"{where}.scale", "a cylinder must scale x and z alike"
        )
        out |= {
            "type": "cylinder",
            "p0": point([0, -1, 0]),
            "p1": point([0, 1, 0]),
            "radius": abs(sc[0]),
        }
    elif kind == "cube":
        # Both are [−1, 1]³ in object space.
        out |= {"type": "cube", "to_world": mi.ScalarTransform4f(m.tolist())}
    elif kind in ("plane", "square"):
        # y = 0 in object space; Mitsuba's rectangle is z = 0, |x|, |y| ≤ 1.
        half = PLANE_HALF_SIDE if kind == "plane" else 1.0
        lift = np.array(
            [[half, 0, 0, 0], [0, 0, half, 0], [0, -half, 0, 0], [0, 0, 0, 1.0]]
        )
        out |= {"type": "rectangle", "to_world": mi.ScalarTransform4f((m @ lift).tolist())}
    elif kind == "disk":
        lift = np.array([[1.0, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]])
        out |= {"type": "disk", "to_world": mi.ScalarTransform4f((m @ lift).tolist())}
    else:
        raise SceneError(f"{where}.shape: {kind!r} has no Mitsuba counterpart here")
    return out


def mitsuba_scene(mi, scene, size):
    """The Mitsuba scene dict for an fpgfx scene file (already parsed)."""
    r = scene.get("render", {})
    refuse_unless(
        list(r.get("background", [0, 0, 0])) == [0, 0, 0],
        "render.background",
        "must be black (Mitsuba's would be an emitter)",
    )
    refuse_unless(r.get("spp", 1) == 1, "render.spp", "the comparison is at 1 spp")
    refuse_unless("ambient" not in scene, "ambient", "Mitsuba has no ambient term")
    cam = scene["camera"]
    width, height = size
    out = {
        "type": "scene",
        "integrator": {
            "type": "direct",
            "emitter_samples": 1,
            "bsdf_samples": 0,
        },
        "sensor": {
            "type": "perspective",
            "fov": cam["fov_y"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["position"], target=cam["look_at"], up=cam["up"]
            ),
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
            "sampler": {"type": "independent", "sample_count": 1},
        },
    }
    for i, light in enumerate(scene.get("light", [])):
        refuse_unless(
            "direction" not in light, f"light[{i}].direction", "only point lights"
        )
        out[f"light{i}"] = {
            "type": "point",
            "position": light["position"],
            "intensity": {"type": "rgb", "value": light["color"]},
        }
    bsdfs = {}
    for name, mat in scene.get("material", {}).items():
        bsdfs[name] = bsdf(name, mat)
        out[name] = bsdfs[name] | {"id": name}
    for i, obj in enumerate(scene.get("object", [])):
        out[f"object{i}"] = shape(mi, i, obj, bsdfs)
    return out


def time_mitsuba(variant, scene, size, runs):
    """Seconds of each timed render call, the first (compiling) call and the frame."""
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    s = mi.load_dict(mitsuba_scene(mi, scene, size))

    def once():
        t = time.perf_counter()
        img = mi.render(s, spp=1)
        dr.eval(img)
        dr.sync_thread()
        return time.perf_counter() - t, img

    first, img = once()
    times = [once()[0] for _ in range(runs)]
    return times, first, np.array(img)


def time_fpgfx(fpgfx, scene_path, out_png, runs):
    """Seconds of each whole `fpgfx render` process, after one untimed run."""
    cmd = [str(fpgfx), "render", str(scene_path), "-o", str(out_png)]
    subprocess.run(cmd, check=True, capture_output=True)
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return times


def psnr(a, b):
    mse = float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))
    return math.inf if mse == 0 else 10 * math.log10(255.0**2 / mse)


def mismatch_mask(ours, theirs, levels=8):
    """White where a pixel is more than `levels` apart in some channel while its 3×3
    neighbourhood in fpgfx's frame is flat (no channel spans more than `levels`): where
    neither an edge nor a shadow boundary lets pixel-centre and random in-pixel samples
    differ. An RGB image, so that it can be written beside the frames."""
    a = ours.astype(np.int16)
    h, w, _ = a.shape
    pad = np.pad(a, ((1, 1), (1, 1), (0, 0)), mode="edge")
    shifted = [
        pad[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w]
        for dy in (-1, 0, 1)
        for dx in (-1, 0, 1)
    ]
    span = (np.max(shifted, axis=0) - np.min(shifted, axis=0)).max(axis=2)
    diff = np.abs(a - theirs.astype(np.int16)).max(axis=2)
    bad = (diff > levels) & (span <= levels)
    return np.repeat((bad * 255).astype(np.uint8)[:, :, None], 3, axis=2)


def off_edge_mismatches(ours, theirs):
    """How many pixels [`mismatch_mask`] marks."""
    return int(np.count_nonzero(mismatch_mask(ours, theirs)[:, :, 0]))


def write_png(mi, path, rgb8):
    """An (H, W, 3) uint8 array as a PNG, values as they are (no gamma applied)."""
    mi.Bitmap(np.ascontiguousarray(rgb8), mi.Bitmap.PixelFormat.RGB).write(str(path))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fpgfx", required=True, help="the fpgfx binary (release build)")
    p.add_argument("--scene", required=True, help="an fpgfx scene file (TOML)")
    p.add_argument("--runs", type=int, default=5, help="timed runs of each renderer")
    p.add_argument(
        "--out",
        required=True,
        help="directory for the frames (fpgfx.png, mitsuba-VARIANT.png, their off-edge "
        "mismatches as mismatch-VARIANT.png) and figures.json",
    )
    a = p.parse_args()
    if a.runs < 1:
        p.error("--runs must be at least 1")

    path = Path(a.scene)
    try:
        scene = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as e:
        sys.exit(f"compare.py: {path}: {e}")
    size = scene.get("render", {}).get("size")
    if not (isinstance(size, list) and len(size) == 2):
        sys.exit(f"compare.py: {path}: render.size: expected [width, height]")

    import mitsuba as mi

    try:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        png = out / "fpgfx.png"
        fp = time_fpgfx(a.fpgfx, path, png, a.runs)
        mi.set_variant("scalar_rgb")
        ours = np.array(mi.Bitmap(str(png)))
        results = {}
        for variant in ("llvm_ad_rgb", "scalar_rgb"):
            times, first, img = time_mitsuba(variant, scene, size, a.runs)
            theirs = np.floor(np.clip(img, 0.0, 1.0) * 255.0).astype(np.uint8)
            write_png(mi, out / f"mitsuba-{variant}.png", theirs)
            write_png(mi, out / f"mismatch-{variant}.png", mismatch_mask(ours, theirs))
            results[variant] = (
                times,
                first,
                psnr(ours, theirs),
                off_edge_mismatches(ours, theirs),
            )
    except SceneError as e:
        sys.exit(f"compare.py: {path}: {e}")

    fp_best = min(fp)
    print(f"scene {path}, {size[0]}x{size[1]}, 1 spp, best of {a.runs} (median in brackets)")
    print(
        f"{'renderer':<34} {'seconds':>18} {'fpgfx is':>10} {'PSNR vs fpgfx':>14}"
        f" {'off-edge px > 8':>16}"
    )
    print(
        f"{'fpgfx render, whole process':<34} "
        f"{fp_best:>8.3f} ({statistics.median(fp):.3f}) {'1.00x':>10} {'':>14}"
    )
    figures = {"scene": str(path), "size": size, "runs": a.runs, "fpgfx_s": fp}
    ok = True
    limit = MAX_OFF_EDGE * size[0] * size[1]
    for variant, (times, first, q, off) in results.items():
        best = min(times)
        print(
            f"{'Mitsuba ' + variant + ', render call':<34} "
            f"{best:>8.3f} ({statistics.median(times):.3f}) "
            f"{best / fp_best:>9.2f}x {q:>11.1f} dB {off:>16}"
        )
        figures[variant] = {
            "render_s": times,
            "first_call_s": first,
            "psnr_db": q,
            "off_edge_mismatches": off,
        }
        ok &= off <= limit
    print("(fpgfx is: Mitsuba's best time over fpgfx's; > 1 means fpgfx is faster)")
    for variant, (_, first, _, _) in results.items():
        print(f"Mitsuba {variant}: first call (compiles its kernels) {first:.3f} s, untimed")
    (out / "figures.json").write_text(json.dumps(figures, indent=2))
    print(f"frames, mismatch masks and figures.json in {out}")
    if not ok:
        sys.exit(
            f"compare.py: more than {limit:.0f} pixels away from edges differ by more "
            "than 8 levels: the two renderers did not draw the same scene, so the times "
            "do not compare"
        )


if __name__ == "__main__":
    main()
