"""The bounds urdf2dh puts on what it reads, so that no input makes it run for minutes, take
gigabytes or crash: each is refused beyond, with a one-line error naming the bound.
``docs/limits.md`` lists them all with the error each gives.

The chain-length bounds are set from measurements (``benchmarks/scale.py``): ``convert``
takes about 0.5 ms and 8 kB per joint (a chain of :data:`JOINTS` joints in ~5 s and 200 MB);
Pinocchio's URDF parser, which ``verify`` runs, recurses once per link (a segmentation fault
beyond ~3,700 links on an 8 MiB stack, so it runs on a thread of :data:`PINOCCHIO_STACK`
bytes) and takes time that grows faster than the links.
"""

from __future__ import annotations

__all__ = [
    "FILE_BYTES",
    "JOINTS",
    "JOINT_POSITIONS",
    "MAPPING_DEPTH",
    "MAPPING_VALUES",
    "PINOCCHIO_STACK",
    "VERIFY_JOINTS",
]

# Bytes of any file urdf2dh reads (SOURCE, a measurement CSV, a marker layout): a URDF of
# JOINTS joints is ~3 MB, a POE or table file of as many joints under 2 MB.
FILE_BYTES = 16 * 2**20

# Values of a parsed POE or table file, aliases counted each time they are used: a YAML file
# of a few hundred bytes can otherwise alias its way to billions ("billion laughs").
MAPPING_VALUES = 1_000_000

# Levels of nesting of a POE or table file (lists and mappings in one another): a POE file has
# four.
MAPPING_DEPTH = 1_000

# Joints of a URDF (all its joints, on the chain or not), of a POE or table file, and of a
# xacro file's expansion.
JOINTS = 10_000

# Values of a parsed POE or table file, aliases counted each time they are used: a YAML file
# of a few hundred bytes can otherwise alias its way to billions ("billion laughs").
MAPPING_VALUES = 1_000_000

# Levels of nesting of a POE or table file (lists and mappings in one another): a POE file has
# four.
MAPPING_DEPTH = 1_000

# Configurations x joints of one self-check, verify run or synthesized set of poses: 80 MB for
# each array of joint positions (a check of 1,000 configurations of a JOINTS-joint chain).
JOINT_POSITIONS = 10_000_000

# Joints of a URDF (or of a POE or table chain) that `verify` hands to Pinocchio: building
# its model of 2,000 joints takes ~1 s and 200 MB, of 8,000 joints 25 s and 2 GB.
VERIFY_JOINTS = 2_000

# Stack of the thread that runs Pinocchio's URDF parser (bytes), whatever the process's own
# stack limit: ample for VERIFY_JOINTS links.
PINOCCHIO_STACK = 256 * 2**20
