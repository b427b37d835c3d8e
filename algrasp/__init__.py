"""algrasp: sensorless orienting of algebraic planar parts with a parallel-jaw gripper."""

__version__ = "0.1.0"
