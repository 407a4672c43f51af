"""Time the default `beam render` against `--method ray` (its default 64 spp) on the built-in scenes
and the shared ones, as a new user would run them: wall seconds of the whole command (loading,
building, rendering, writing the PNG), best of `runs` (3 unless given), the two methods' runs
interleaved. The table of docs/benchmarks.md.

    python3 docs/default_vs_ray.py target/release/beam [size [runs]]      (BEAM_SCENES: ../shared/scenes)
"""
import os, subprocess, sys, tempfile, time

beam, size = sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "512"
runs = int(sys.argv[3]) if len(sys.argv) > 3 else 3
shared = os.environ.get("BEAM_SCENES", "../shared/scenes")
scenes = ["cornell", "cornell-point", "mirror-glass", "foliage", "spheres", "spheres-36", "plant", "ground"]
scenes += [os.path.join(shared, f) for f in ["conference/conference.obj", "cornell_box_mcguire/CornellBox-Original.obj",
                                              "sibenik/sibenik.obj", "sponza_dabrovic/sponza.obj",
                                              "spot/spot_triangulated.obj", "stanford_bunny/stanford-bunny.obj",
                                              "teapot/teapot.obj"]]
scenes.append("spheres-256")
out = os.path.join(tempfile.mkdtemp(), "x.png")
print(f"{'scene':28s} {'beam s':>8s} {'ray s':>8s} ratio   ({size}², best of {runs})")
for scene in scenes:
    if scene.endswith(".obj") and not os.path.exists(scene):
        print(f"skipping {scene}: not found")
        continue
    times = {"beam": [], "ray": []}
    for _ in range(runs):
        for method in times:
            t = time.time()
            cmd = [beam, "render", "--scene", scene, "--width", size, "--height", size, "--method", method, "--out", out]
            subprocess.run(cmd, check=True, capture_output=True)
            times[method].append(time.time() - t)
    best = [min(times["beam"]), min(times["ray"])]
    print(f"{os.path.basename(scene):28s} {best[0]:8.3f} {best[1]:8.3f} {best[0] / best[1]:5.2f}", flush=True)
