"""Gymnasium environments around hippo's robot, and a wrapper that exposes hippo's cells.

Importing :mod:`hippo.envs` registers three environments::

    import gymnasium as gym
    import hippo.envs  # noqa: F401  (registers the ids)

    env = gym.make("hippo/PlacePreference-v0", render_mode="rgb_array")
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

(``gym.make("hippo.envs:hippo/TwoRooms-v0")`` imports the module itself.)

- ``hippo/TwoRooms-v0``: SMC09's two rooms, +1 for reaching the other room; time limit
  3000 ticks (10 min).
- ``hippo/PlacePreference-v0``: HIREL III-A, stand still in the goal zone for 7 s (+1 with
  the sound, and the episode ends); 1200 ticks (4 min).
- ``hippo/Patrol-v0``: HIREL III-B, wait at checkpoints 1, 2, 3 in turn (+1 with the sound
  at each); 6000 ticks (20 min).

Observations are the robot's senses (:mod:`hippo.envs.robot`), actions normalised wheel speeds,
ground truth only in ``info``. :class:`HippoCells` adds place-cell and time-cell activities.
"""

from gymnasium.envs.registration import register, registry

from hippo.envs.rewards import GoalWaitTask, PatrolTask, ShuttleTask, Task
from hippo.envs.robot import PatrolEnv, PlacePreferenceEnv, RobotEnv, TwoRoomsEnv
from hippo.envs.wrappers import HippoCells

#: registered id -> (entry point, max_episode_steps)
ENVIRONMENTS: dict[str, tuple[str, int]] = {
    "hippo/TwoRooms-v0": ("hippo.envs.robot:TwoRoomsEnv", 3000),
    "hippo/PlacePreference-v0": ("hippo.envs.robot:PlacePreferenceEnv", 1200),
    "hippo/Patrol-v0": ("hippo.envs.robot:PatrolEnv", 6000),
}


def register_envs() -> None:
    """Register hippo's environments with Gymnasium (done on import; safe to call again)."""
    for env_id, (entry_point, steps) in ENVIRONMENTS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point, max_episode_steps=steps)


register_envs()

__all__ = [
    "ENVIRONMENTS", "GoalWaitTask", "HippoCells", "PatrolEnv", "PatrolTask",
    "PlacePreferenceEnv", "RobotEnv", "ShuttleTask", "Task", "TwoRoomsEnv", "register_envs",
]
