"""The robot's world: pymunk physics, arenas, controllers, the teacher, recordings.

Quick start::

    from hippo.sim import World, arenas, WallFollower
    world = World(arenas.two_rooms(), sensors="ir8", seed=0)
    ctrl = WallFollower(rng=0)
    obs = world.reset(seed=0)
    for _ in range(100):
        obs = world.step(ctrl.act(obs))
"""

from hippo.sim import arenas
from hippo.sim.arena import Arena, Region, Zone
from hippo.sim.builder import ArenaBuilder
from hippo.sim.controllers import (
    AvoidanceParams,
    GoToHeading,
    ObstacleAvoidance,
    Stop,
    WallFollower,
    WallFollowerParams,
)
from hippo.sim.odometry import PathIntegrator
from hippo.sim.record import Recording, record
from hippo.sim.robot import IR8, RAY17, RobotParams, SensorModel
from hippo.sim.teacher import Teacher
from hippo.sim.world import GroundTruth, Intervention, Observation, World, wrap_angle

__all__ = [
    "IR8", "RAY17", "Arena", "ArenaBuilder", "AvoidanceParams", "GoToHeading", "GroundTruth",
    "Intervention", "Observation",
    "ObstacleAvoidance", "PathIntegrator", "Recording", "Region", "RobotParams", "SensorModel",
    "Stop", "Teacher", "WallFollower", "WallFollowerParams", "World", "Zone", "arenas", "record",
    "wrap_angle",
]
