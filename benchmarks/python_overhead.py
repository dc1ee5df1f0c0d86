"""The Python module's overhead per call against the C API: the same rays traced on the same
fully built BVH by lt_structure_trace in C (bench_overhead) and by Structure.intersect from
Python, with float32 and float64 input, for batches of 10, 10k and 1M rays. The machine is
shared and noisy, so C and Python take turns: ROUNDS rounds, each timing C's calls and then
Python's; a round's figure is the median of its calls, and the table gives the median over
rounds, and the median of the rounds' paired differences (the overhead). Because separate
processes differ by more than the overhead on small batches, each round also times, in the
same process, lt_structure_trace called through ctypes on records packed beforehand: what
Structure.intersect adds to it is the module's own work (checking, converting and packing the
arrays, unpacking the hits). Prints markdown.
    python_overhead.py BUILD_DIR SCENE ROUNDS DEVICE..."""
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import lazytrace

# Batch sizes and calls timed per round (fewer for the long ones).
SIZES = {10: 51, 10_000: 21, 1_000_000: 3}


def rays_for(scene, n, seed=1):
    lo, hi = (b.astype(np.float64) for b in scene.bounds)
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(lo, hi, (n, 3)), rng.uniform(lo, hi, (n, 3))
    rays = np.zeros(n, lazytrace.RAY_DTYPE)
    rays["org"], rays["dir"], rays["tmax"] = a, b - a, np.inf
    return rays


def median_ms(call, runs):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        call()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def c_round(build, spec, ray_path, device):
    """One run of the C program: {N: median ms}."""
    out = subprocess.run([f"{build}/benchmarks/bench_overhead", spec, ray_path, device]
                         + [f"{n}:{runs}" for n, runs in SIZES.items()],
                         check=True, capture_output=True, text=True).stdout
    return {int(n): float(ms) for n, ms in (line.split() for line in out.splitlines())}


def main():
    build, spec, rounds, devices = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
    scene = lazytrace.Scene.load(spec)
    rays = rays_for(scene, max(SIZES))
    inputs = {n: (np.ascontiguousarray(rays["org"][:n]), np.ascontiguousarray(rays["dir"][:n])) for n in SIZES}
    print(f"`{spec}`: {scene.triangle_count} triangles, full BVH, closest hit, random rays through the scene's box."
          f" {rounds} rounds, C then Python in each; calls per round: "
          + ", ".join(f"{runs} of {n:,} rays" for n, runs in SIZES.items())
          + ". Medians over rounds; the overhead is the median of the rounds' (Python float32 - C).\n")
    print("| device | rays | C API ms | Python ms (float32 in) | Python ms (float64 in) | Python - C | Python / C |"
          " module's own work |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.NamedTemporaryFile(suffix=".rays") as ray_file:
        rays.tofile(ray_file.name)
        for device in devices:
            structure = lazytrace.Structure(scene, kind="bvh", build="full",
                                            context=lazytrace.Context(device, quiet=True))
            structure.intersect(rays["org"], rays["dir"])  # warm-up, as the C program does
            c, py32, py64, raw = ({n: [] for n in SIZES} for _ in range(4))
            records = {n: np.ascontiguousarray(rays[:n]) for n in SIZES}
            hits = np.empty(len(rays), lazytrace.HIT_DTYPE)
            trace = lazytrace._lib.lt_structure_trace
            for _ in range(rounds):
                for n, ms in c_round(build, spec, ray_file.name, device).items():
                    c[n].append(ms)
                for n, runs in SIZES.items():
                    o32, d32 = inputs[n]
                    o64, d64 = o32.astype(np.float64), d32.astype(np.float64)
                    py32[n].append(median_ms(lambda: structure.intersect(o32, d32), runs))
                    py64[n].append(median_ms(lambda: structure.intersect(o64, d64), runs))
                    raw[n].append(median_ms(lambda: trace(structure._handle, records[n].ctypes.data, n, 0,
                                                          hits.ctypes.data, None), runs))
            for n in SIZES:
                med = statistics.median
                overhead = med(p - q for p, q in zip(py32[n], c[n]))
                ratio = med(p / q for p, q in zip(py32[n], c[n]))
                own = med(p - q for p, q in zip(py32[n], raw[n]))
                print(f"| {device} | {n:,} | {med(c[n]):.3f} | {med(py32[n]):.3f} | {med(py64[n]):.3f} |"
                      f" {overhead * 1e3:.0f} us | {ratio:.2f}x | {own * 1e3:.0f} us |")


if __name__ == "__main__":
    main()
