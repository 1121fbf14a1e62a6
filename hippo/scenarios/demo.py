"""Drive the e-puck with SMC09's wall follower in the two-rooms arena and draw its path."""

from __future__ import annotations

import argparse
import time

import numpy as np

from hippo.cli_args import integer, probability
from hippo.io import save_figure
from hippo.plots.sim import plot_sensor_strip, plot_trajectory
from hippo.scenarios._common import prepare_out, write_metrics
from hippo.sim import arenas
from hippo.sim.record import record


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--arena", default="two-rooms", choices=list(arenas.ARENAS),
                        help="the arena")
    parser.add_argument("--ticks", type=integer(2, 10_000_000), default=6000,
                        help="control ticks of 0.2 s")
    parser.add_argument("--rho", type=probability, default=0.008,
                        help="side-switch probability of the wall follower per tick")


def run(args: argparse.Namespace) -> dict:
    out = prepare_out(args.out)
    arena = arenas.get(args.arena)
    ticks = min(args.ticks, 1000) if args.quick else args.ticks
    sensors = "ray17" if arena.name == "maze-e1" else "ir8"
    t0 = time.perf_counter()
    rec = record(arena, ticks, seed=args.seed, rho=args.rho, sensors=sensors)
    wall = time.perf_counter() - t0
    rec.save(out / "run.npz")
    fig, _ = plot_trajectory(arena, rec)
    save_figure(fig, out / "trajectory.png", dpi=120)
    fig, _ = plot_sensor_strip(rec, 0, min(len(rec), 1500))
    save_figure(fig, out / "sensors.png", dpi=120)
    visited = {name: float(np.mean(rec.region == i)) for i, name in enumerate(rec.region_names)}
    metrics = {
        "arena": arena.name, "ticks": ticks, "seed": args.seed, "rho": args.rho,
        "simulated_s": float(rec.t[-1]), "wall_s": wall, "ticks_per_s": ticks / wall,
        "region_occupancy": visited,
        "locations_visited": len(np.unique(rec.label)),
        "mean_speed_cm_s": float(rec.speed.mean()),
    }
    write_metrics(out, metrics, summary=(
        f"demo: {ticks} ticks ({metrics['simulated_s']:.0f} s simulated) in {arena.name}, "
        f"{metrics['locations_visited']} of {len(arena.locations)} labelled locations visited, "
        f"mean speed {metrics['mean_speed_cm_s']:.1f} cm/s, {metrics['ticks_per_s']:.0f} ticks/s"))
    return metrics
