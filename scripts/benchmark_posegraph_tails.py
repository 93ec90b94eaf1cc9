#!/usr/bin/python3
"""Slow tails on simulated pose graphs with heavy rotation noise (issue 27).

For each case, `slam simulate` writes a lattice world (grid2d: 2500 poses on
a 35 x 35 lattice; grid3d: 1000 poses on 10^3 or 2500 on 14^3), loop closures
with probability 0.5, 0.15 m translation noise and the given rotation noise
on every measurement; then `slam optimize --init chordal` solves it with the
default settings and once more as a long LM run (no probe, 1000 iterations,
tight tolerances). Prints one markdown table: iterations of the default, its
chi2, the long run's, and the relative gap (the tails test asks for <= 15
iterations and 1e-6).

  /usr/bin/python3 scripts/benchmark_posegraph_tails.py [--slam build/apps/slam]
      [--only grid3d]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

LONG_RUN = """optimize:
  init: chordal
  gauss_newton_probe_iterations: 0
  max_iterations: 1000
  function_tolerance: 1e-12
  gradient_tolerance: 1e-14
  parameter_tolerance: 1e-12
"""


def cases():
    for sigma in (0.25, 0.3, 0.35):
        for seed in range(1, 9):
            yield ("grid2d", 2500, 35, sigma, seed)
    for seed in range(1, 5):
        yield ("grid3d", 2500, 14, 0.2, seed)
    for seed in range(1, 4):
        yield ("grid3d", 1000, 10, 0.25, seed)


def simulate_config(world, num_poses, grid_size, sigma, seed):
    return f"""simulate:
  seed: {seed}
  world:
    type: {world}
    num_poses: {num_poses}
    grid_size: {grid_size}
  odometry:
    sigma_translation: 0.15
    sigma_rotation: {sigma}
  loop_closures:
    sigma_translation: 0.15
    sigma_rotation: {sigma}
    probability: 0.5
"""


def optimize(slam, graph, out, report, config=None):
    command = [slam, "optimize", "-i", graph, "-o", out, "--init", "chordal",
               "--report", report]
    if config is not None:
        command += ["--config", config]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(report) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--slam", default="build/apps/slam")
    parser.add_argument("--only", default="", help="substring of the case")
    args = parser.parse_args()
    if not os.path.exists(args.slam):
        sys.exit(f"no slam binary at {args.slam}")
    print("| world | poses | rot. noise rad | seed | iterations | final chi2 | "
          "long run iterations | long run chi2 | rel. gap | ok |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        long_config = os.path.join(tmp, "long.yaml")
        with open(long_config, "w") as f:
            f.write(LONG_RUN)
        for world, poses, grid, sigma, seed in cases():
            name = f"{world} {poses} {sigma} {seed}"
            if args.only not in name:
                continue
            folder = os.path.join(tmp, name.replace(" ", "_"))
            config = folder + ".yaml"
            with open(config, "w") as f:
                f.write(simulate_config(world, poses, grid, sigma, seed))
            subprocess.run([args.slam, "simulate", "--config", config, "-o",
                            folder], check=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
            graph = os.path.join(folder, "graph.g2o")
            out = os.path.join(folder, "out.g2o")
            fast = optimize(args.slam, graph, out,
                            os.path.join(folder, "fast.json"))
            best = optimize(args.slam, graph, out,
                            os.path.join(folder, "long.json"), long_config)
            gap = (fast["final_chi2"] - best["final_chi2"]) / best["final_chi2"]
            ok = fast["iterations"] <= 15 and gap <= 1e-6
            print(f"| {world} | {poses} | {sigma} | {seed} | "
                  f"{fast['iterations']} | {fast['final_chi2']:.10g} | "
                  f"{best['iterations']} | {best['final_chi2']:.10g} | "
                  f"{gap:.1e} | {'yes' if ok else 'NO'} |", flush=True)


if __name__ == "__main__":
    main()
