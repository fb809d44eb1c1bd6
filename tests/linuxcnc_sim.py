"""Run a HAL file of ours in LinuxCNC itself and evaluate the real genserkins on it.

Run by Debian's Python (``/usr/bin/python3``: LinuxCNC's ``hal`` module is built for it), not
by the project's; it needs only the standard library and Debian's ``linuxcnc-uspace``:

    /usr/bin/python3 tests/linuxcnc_sim.py REQUEST.json ANSWER.json

The request is ``{"files": [{"hal": TEXT, "q": [[q0..q5 degrees], ...]}, ...]}``: the arm's
joint positions, as its drives report them. For each file, in a realtime-less uspace session:

1. LinuxCNC's ``realtime`` starts (POSIX threads, no realtime kernel) and ``servo-thread`` is
   made as motmod makes it (``threads``, 1 ms);
2. genserkins (``/usr/lib/linuxcnc/modules/genserkins.so``, Debian's build) is loaded into this
   process as a HAL component, its ``rtapi_app_main`` creating its pins, because its forward
   kinematics is a C function (``kinematicsForward``) that motmod calls, not a HAL function;
3. ``halcmd -f FILE`` runs the file: its ``setp genserkins.*`` set the real component's pins, its
   ``loadrt scale`` / ``addf`` / ``setp`` lines build the joint-zero components in servo-thread;
4. for each configuration the drives' feedback ``q_i`` goes into ``urdf2dh-fb-i.in`` (joints
   without one take ``q_i`` as it is, as motion would), servo-thread runs, and the
   ``urdf2dh-fb-i.out`` values are genserkins' joints; motion's command path is checked too
   (``urdf2dh-cmd-i`` of those angles gives back the drive position). Then genserkins'
   ``kinematicsForward`` of those joints (what motmod calls with the joint feedback) gives the
   Cartesian pose ``x y z a b c`` as LinuxCNC reports it.

Pins are read with LinuxCNC's ``hal.get_value`` (full doubles; ``halcmd getp`` prints 7
digits) and set with ``hal.set_p`` (parsed with ``strtod``, as ``setp`` parses). The answer is
``{"linuxcnc": VERSION, "files": [{"joints": ..., "commands": ..., "poses": ...}]}`` (a file:
genserkins prints on this process's stdout).

HAL's shared memory is one per machine, so sessions take a lock file; a session that fails
stops its realtime before it exits.
"""

from __future__ import annotations

import ctypes
import fcntl
import json
import os
import pwd
import subprocess
import sys
import tempfile
import time

MODULES = "/usr/lib/linuxcnc/modules"
REALTIME = "/usr/lib/linuxcnc/realtime"
LOCK = os.path.join(tempfile.gettempdir(), "urdf2dh-linuxcnc-sim.lock")
JOINTS = 6
SENTINEL = "urdf2dh-sim-sentinel"  # a sum2 after every function: proves a servo period ran


class EmcPose(ctypes.Structure):
    """``EmcPose`` (emcpos.h): ``PmCartesian tran`` then ``a b c u v w``, all doubles."""

    _fields_ = [(name, ctypes.c_double) for name in ("x", "y", "z", "a", "b", "c", "u", "v", "w")]


class Session:
    """One realtime session: start, commands, stop (whatever happened in between)."""

    def __init__(self, workdir: str) -> None:
        self.env = dict(os.environ, HAL_RTMOD_DIR=MODULES)
        self.env["RTAPI_FIFO_PATH"] = os.path.join(workdir, "rtapi_fifo")
        if os.getuid() == 0:  # rtapi_app refuses root without a fallback user to drop to
            nobody = pwd.getpwnam("nobody").pw_uid
            self.env["RTAPI_UID"] = str(nobody)
            os.chown(workdir, nobody, -1)
        self.log = open(os.path.join(workdir, "hal.log"), "w+")
        os.environ.update(self.env)  # the hal module and genserkins attach with the same
        self.genserkins: ctypes.CDLL | None = None
        self.started = False  # only a realtime this session started is stopped

    def run(self, *argv: str) -> None:
        # rtapi_app stays running after `realtime start`: it must not hold a pipe of ours
        proc = subprocess.run(
            argv, env=self.env, stdin=subprocess.DEVNULL, stdout=self.log, stderr=self.log,
            timeout=60,
        )  # fmt: skip
        if proc.returncode != 0:
            self.log.seek(0)
            tail = self.log.read()[-2000:]
            raise RuntimeError(f"{' '.join(argv)} exited {proc.returncode}:\n{tail}")

    def start(self) -> None:
        status = subprocess.run(
            [REALTIME, "status"], env=self.env, stdin=subprocess.DEVNULL, stdout=self.log,
            stderr=self.log, timeout=60,
        )  # fmt: skip
        if status.returncode == 0:  # never touch a LinuxCNC that is not ours
            raise RuntimeError(
                "LinuxCNC's realtime is already running on this machine (another LinuxCNC, or "
                "a session left over); stop it with `halrun -U` and run again"
            )
        self.run(REALTIME, "start")
        self.started = True
        self.run("halcmd", "loadrt", "threads", "name1=servo-thread", "period1=1000000")
        ctypes.CDLL("liblinuxcnchal.so.0", mode=ctypes.RTLD_GLOBAL)
        self.genserkins = ctypes.CDLL(f"{MODULES}/genserkins.so", mode=ctypes.RTLD_GLOBAL)
        if self.genserkins.rtapi_app_main() != 0:
            raise RuntimeError("genserkins' rtapi_app_main failed")
        self.run("halcmd", "loadrt", "sum2", f"names={SENTINEL}")

    def stop(self) -> None:
        if self.genserkins is not None:
            self.genserkins.rtapi_app_exit()
        if not self.started:
            self.log.close()
            return
        for argv in (("halcmd", "stop"), ("halcmd", "unload", "all"), (REALTIME, "stop")):
            try:
                self.run(*argv)
            except (RuntimeError, subprocess.TimeoutExpired):
                pass
        self.log.close()

    def forward(self, joints: list[float]) -> list[float]:
        """genserkins' ``kinematicsForward`` of joint positions in degrees."""
        assert self.genserkins is not None
        values = (ctypes.c_double * 9)(*joints, 0.0, 0.0, 0.0)
        pose = EmcPose()
        fflags, iflags = ctypes.c_ulong(0), ctypes.c_ulong(0)
        status = self.genserkins.kinematicsForward(
            values, ctypes.byref(pose), ctypes.byref(fflags), ctypes.byref(iflags)
        )
        if status != 0:
            raise RuntimeError(f"kinematicsForward returned {status} at {joints}")
        return [pose.x, pose.y, pose.z, pose.a, pose.b, pose.c]


def settle(hal, count: int) -> int:
    """Wait until servo-thread has run two whole periods after now (the sentinel, last in the
    thread, shows each number it was given only after the functions before it ran)."""
    for _ in range(2):
        count += 1
        hal.set_p(f"{SENTINEL}.in0", str(count))
        deadline = time.monotonic() + 10.0
        while hal.get_value(f"{SENTINEL}.out") != count:
            if time.monotonic() > deadline:
                raise RuntimeError("servo-thread did not run within 10 s")
            time.sleep(0.0005)
    return count


def evaluate(session: Session, hal, text: str, configs: list[list[float]], workdir: str) -> dict:
    path = os.path.join(workdir, "export.hal")
    with open(path, "w") as f:
        f.write(text)
    session.run("halcmd", "-f", path)
    session.run("halcmd", "addf", SENTINEL, "servo-thread")  # after the file's functions
    session.run("halcmd", "start")
    pins = {p["NAME"] for p in hal.get_info_pins()}
    mapped = [i for i in range(JOINTS) if f"urdf2dh-fb-{i}.in" in pins]
    out: dict[str, list] = {"joints": [], "commands": [], "poses": []}
    count = 0
    for q in configs:
        for i in mapped:
            hal.set_p(f"urdf2dh-fb-{i}.in", repr(float(q[i])))
        count = settle(hal, count)
        joints = [
            hal.get_value(f"urdf2dh-fb-{i}.out") if i in mapped else float(q[i])
            for i in range(JOINTS)
        ]
        for i in mapped:
            hal.set_p(f"urdf2dh-cmd-{i}.in", repr(joints[i]))
        count = settle(hal, count)
        commands = [
            hal.get_value(f"urdf2dh-cmd-{i}.out") if i in mapped else joints[i]
            for i in range(JOINTS)
        ]
        out["joints"].append(joints)
        out["commands"].append(commands)
        out["poses"].append(session.forward(joints))
    session.run("halcmd", "stop")
    session.run("halcmd", "delf", SENTINEL, "servo-thread")
    if mapped:
        session.run("halcmd", "unload", "scale")
    return out


def version() -> str:
    proc = subprocess.run(
        ["dpkg-query", "-W", "-f", "${Version}", "linuxcnc-uspace"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    return proc.stdout.strip() or "unknown"


def main() -> int:
    with open(sys.argv[1]) as f:
        request = json.load(f)
    with open(LOCK, "w") as lock, tempfile.TemporaryDirectory(prefix="urdf2dh-hal-") as work:
        fcntl.flock(lock, fcntl.LOCK_EX)
        session = Session(work)
        try:
            session.start()
            import hal  # LinuxCNC's, attached to the session's shared memory

            files = [
                evaluate(session, hal, item["hal"], item["q"], work) for item in request["files"]
            ]
        finally:
            session.stop()
    with open(sys.argv[2], "w") as f:
        json.dump({"linuxcnc": version(), "files": files}, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
