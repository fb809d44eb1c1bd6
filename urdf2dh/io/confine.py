"""What a child process that runs an untrusted file does to itself first (see ``docs/security.md``).

Four layers, each one holding if the others are got round:

* :func:`limit`: resource limits: address space and CPU time bounded, no file may grow (so none
  is written), no new process for an ordinary user (``RLIMIT_NPROC`` 0; the kernel does not apply
  it to root, whom the next layer stops), no core file;
* :func:`die_with_parent`: the process is killed the moment the process that started it ends,
  even by ``SIGKILL``;
* :func:`forbid_syscalls`: a seccomp filter (Linux on x86-64 and AArch64) makes the kernel refuse
  the system calls that start a program or a process, signal or trace another process, open a
  socket, or create, change or remove a file; they fail with ``EPERM``, for root too, from Python
  or from machine code alike;
* :func:`guard`: a Python audit hook (PEP 578) refuses the same in Python (processes, signals,
  sockets, writing or changing files, ``ctypes``, importing a module not yet imported, the
  introspection attributes that reach frames and code) and records every file the process opens.

Only the standard library is used: this module runs in a child started in isolated mode, whose
``sys.path`` is the standard library's (and it is imported from its file, not as part of urdf2dh).
"""

from __future__ import annotations

import os
import platform
import struct
import sys
from collections.abc import Callable, Iterable

__all__ = ["Refused", "die_with_parent", "forbid_syscalls", "guard", "limit"]


class Refused(PermissionError):
    """An operation the confined process may not do."""


# --------------------------------------------------------------------------- resource limits


def limit(memory_bytes: int, cpu_seconds: int) -> None:
    """Bound address space and CPU time; no file written, no process started, no core file."""
    try:
        import resource
    except ImportError:  # not a POSIX system: the parent's time limit still holds
        return
    limits = [
        (resource.RLIMIT_AS, memory_bytes),
        (resource.RLIMIT_CPU, cpu_seconds),
        (resource.RLIMIT_FSIZE, 0),
        (resource.RLIMIT_CORE, 0),
    ]
    if hasattr(resource, "RLIMIT_NPROC"):
        limits.append((resource.RLIMIT_NPROC, 0))
    for which, value in limits:
        try:
            resource.setrlimit(which, (value, value))
        except (ValueError, OSError):  # above a hard limit already lower: keep that one
            pass


# --------------------------------------------------------------------------- Linux's prctl

PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
PR_SET_SECCOMP = 22
PR_SET_NO_NEW_PRIVS = 38
SECCOMP_MODE_FILTER = 2  # <linux/seccomp.h>


def _prctl() -> Callable[..., int] | None:
    if not sys.platform.startswith("linux"):
        return None
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None
    prctl: Callable[..., int] = libc.prctl
    return prctl


def die_with_parent(parent: int) -> None:
    """Have the kernel send ``SIGKILL`` when the parent ends (Linux); exit now if it already has
    (``parent`` is the pid the parent had)."""
    import signal

    prctl = _prctl()
    if prctl is not None:
        prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent:
        os._exit(1)


# --------------------------------------------------------------------------- seccomp

# Architecture tags (<linux/audit.h>) and the numbers of the system calls refused, from Linux's
# arch/x86/entry/syscalls/syscall_64.tbl and include/uapi/asm-generic/unistd.h (AArch64).
AUDIT_ARCH = {"x86_64": 0xC000003E, "aarch64": 0xC00000B7}
X32_BIT = 0x40000000  # x86-64 system calls of the x32 ABI carry this bit: all refused
PROCESS_CALLS = {  # start a program or a process, trace or read another one, open a socket
    "x86_64": {"fork": 57, "vfork": 58, "clone": 56, "clone3": 435, "execve": 59,
               "execveat": 322, "ptrace": 101, "process_vm_readv": 310,
               "process_vm_writev": 311, "socket": 41, "io_uring_setup": 425,
               "io_uring_enter": 426, "io_uring_register": 427, "pidfd_send_signal": 424,
               "rt_sigqueueinfo": 129, "rt_tgsigqueueinfo": 297, "bpf": 321, "mount": 165,
               "umount2": 166, "pivot_root": 155, "chroot": 161, "reboot": 169,
               "init_module": 175, "finit_module": 313, "delete_module": 176,
               "kexec_load": 246, "kexec_file_load": 320},
    "aarch64": {"clone": 220, "clone3": 435, "execve": 221, "execveat": 281, "ptrace": 117,
                "process_vm_readv": 270, "process_vm_writev": 271, "socket": 198,
                "io_uring_setup": 425, "io_uring_enter": 426, "io_uring_register": 427,
                "pidfd_send_signal": 424, "rt_sigqueueinfo": 138, "rt_tgsigqueueinfo": 240,
                "bpf": 280, "mount": 40, "umount2": 39, "pivot_root": 41, "chroot": 51,
                "reboot": 142, "init_module": 105, "finit_module": 273, "delete_module": 106,
                "kexec_load": 104, "kexec_file_load": 294},
}  # fmt: skip
FILE_CALLS = {  # create, change or remove a file
    "x86_64": {"creat": 85, "truncate": 76, "ftruncate": 77, "rename": 82, "renameat": 264,
               "renameat2": 316, "mkdir": 83, "mkdirat": 258, "rmdir": 84, "link": 86,
               "linkat": 265, "symlink": 88, "symlinkat": 266, "unlink": 87, "unlinkat": 263,
               "chmod": 90, "fchmod": 91, "fchmodat": 268, "fchmodat2": 452, "chown": 92,
               "fchown": 93, "lchown": 94, "fchownat": 260, "mknod": 133, "mknodat": 259,
               "utime": 132, "utimes": 235, "utimensat": 280, "futimesat": 261,
               "setxattr": 188, "lsetxattr": 189, "fsetxattr": 190, "removexattr": 197,
               "lremovexattr": 198, "fremovexattr": 199, "openat2": 437,
               "open_by_handle_at": 304},
    "aarch64": {"truncate": 45, "ftruncate": 46, "renameat": 38, "renameat2": 276,
                "mkdirat": 34, "linkat": 37, "symlinkat": 36, "unlinkat": 35, "fchmod": 52,
                "fchmodat": 53, "fchmodat2": 452, "fchownat": 54, "fchown": 55, "mknodat": 33,
                "utimensat": 88, "setxattr": 5, "lsetxattr": 6, "fsetxattr": 7,
                "removexattr": 14, "lremovexattr": 15, "fremovexattr": 16, "openat2": 437,
                "open_by_handle_at": 265},
}  # fmt: skip
SIGNAL_CALLS = {  # allowed towards this process only (first argument: its pid)
    "x86_64": {"kill": 62, "tkill": 200, "tgkill": 234},
    "aarch64": {"kill": 129, "tkill": 130, "tgkill": 131},
}
OPEN_CALLS = {  # system call -> index of its flags argument: allowed to open for reading only
    "x86_64": {2: 1, 257: 2},  # open(path, flags), openat(dirfd, path, flags)
    "aarch64": {56: 2},  # openat
}
WRITE_FLAGS = 0o1 | 0o2 | 0o100 | 0o1000 | 0o2000  # O_WRONLY O_RDWR O_CREAT O_TRUNC O_APPEND

# classic BPF (<linux/filter.h>) and the filter's results (<linux/seccomp.h>)
LOAD_WORD = 0x20  # BPF_LD | BPF_W | BPF_ABS
JUMP_EQUAL = 0x15  # BPF_JMP | BPF_JEQ | BPF_K
JUMP_AT_LEAST = 0x35  # BPF_JMP | BPF_JGE | BPF_K
JUMP_ANY_BIT = 0x45  # BPF_JMP | BPF_JSET | BPF_K
RETURN = 0x06  # BPF_RET | BPF_K
ALLOW = 0x7FFF0000  # SECCOMP_RET_ALLOW
REFUSE = 0x00050000 | 1  # SECCOMP_RET_ERRNO | EPERM
NR, ARCH, ARGS = 0, 4, 16  # offsets in struct seccomp_data (arguments: 8 bytes each)


def _filter(machine: str, pid: int) -> list[tuple[int, int, int, int]]:
    """The BPF program, as ``(code, jump if true, jump if false, k)`` instructions."""
    refused = sorted({*PROCESS_CALLS[machine].values(), *FILE_CALLS[machine].values()})
    signals = sorted(SIGNAL_CALLS[machine].values())
    opens = OPEN_CALLS[machine]
    # layout (BPF jumps forward only): header, one test per refused call, one per signal call,
    # one per open call, ALLOW, the signal check (2), one flags check per open call (2 each),
    # ALLOW, REFUSE
    tests = len(refused) + len(signals) + len(opens)
    signal_check = 5 + tests + 1
    allow = signal_check + 2 + 2 * len(opens)  # the second ALLOW, the one jumped to
    refuse = allow + 1

    def to(target: int, here: int) -> int:  # a jump offset (from the next instruction)
        return target - here - 1

    program = [
        (LOAD_WORD, 0, 0, ARCH),
        (JUMP_EQUAL, 1, 0, AUDIT_ARCH[machine]),
        (RETURN, 0, 0, REFUSE),  # another ABI's system call numbers (i386 on x86-64)
        (LOAD_WORD, 0, 0, NR),
        (JUMP_AT_LEAST, to(refuse, 4), 0, X32_BIT if machine == "x86_64" else 0xFFFFFFFF),
    ]
    for nr in refused:
        program.append((JUMP_EQUAL, to(refuse, len(program)), 0, nr))
    for nr in signals:
        program.append((JUMP_EQUAL, to(signal_check, len(program)), 0, nr))
    for i, nr in enumerate(opens):
        program.append((JUMP_EQUAL, to(signal_check + 2 + 2 * i, len(program)), 0, nr))
    program.append((RETURN, 0, 0, ALLOW))
    program.append((LOAD_WORD, 0, 0, ARGS))  # the signal's target: this process?
    program.append((JUMP_EQUAL, to(allow, len(program)), to(refuse, len(program)), pid))
    for index in opens.values():
        program.append((LOAD_WORD, 0, 0, ARGS + 8 * index))  # low word of the flags
        program.append(
            (JUMP_ANY_BIT, to(refuse, len(program)), to(allow, len(program)), WRITE_FLAGS)
        )
    program.append((RETURN, 0, 0, ALLOW))
    program.append((RETURN, 0, 0, REFUSE))
    if len(program) != refuse + 1 or not all(
        0 <= j < 256 for _, t, f, _ in program for j in (t, f)
    ):
        raise RuntimeError("the seccomp filter's jumps do not add up")  # a bug in this module
    return program


def forbid_syscalls() -> bool:
    """Install the seccomp filter; whether it could be (Linux on x86-64 or AArch64 only)."""
    machine = platform.machine().lower().replace("arm64", "aarch64").replace("amd64", "x86_64")
    prctl = _prctl()
    if prctl is None or machine not in AUDIT_ARCH or sys.byteorder != "little":
        return False
    import ctypes

    program = _filter(machine, os.getpid())
    code = b"".join(struct.pack("<HBBI", *instruction) for instruction in program)
    buffer = ctypes.create_string_buffer(code, len(code))

    class Program(ctypes.Structure):
        _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]

    fprog = Program(len(program), ctypes.addressof(buffer))
    if prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
        return False
    return prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, ctypes.byref(fprog), 0, 0) == 0


# --------------------------------------------------------------------------- audit hook

PROCESS_EVENTS = frozenset(
    "os.system os.exec os.posix_spawn os.spawn os.fork os.forkpty subprocess.Popen pty.spawn "
    "os.startfile os.kill os.killpg signal.pthread_kill".split()
)
FILE_EVENTS = frozenset(
    "os.remove os.rename os.rmdir os.mkdir os.chmod os.chown os.chflags os.lchflags os.link "
    "os.symlink os.truncate os.utime os.mkfifo os.mknod os.setxattr os.removexattr "
    "shutil.copyfile shutil.copymode shutil.copystat shutil.copytree shutil.rmtree shutil.move "
    "shutil.make_archive shutil.chown tempfile.mkstemp tempfile.mkdtemp".split()
)
REFUSED_PREFIXES = (
    "socket.",
    "ctypes.",
    "sys._getframe",
    "sys._current_frames",
    "object.__getattr__",
)
WRITE_MODE = frozenset("wax+")


def guard(opened: list[str], imports: Iterable[str] = ("encodings.",)) -> None:
    """Refuse, from now on, what the module docstring lists; append the path of every file opened
    to ``opened``. Modules whose names start with one of ``imports`` may still be imported."""
    allowed = tuple(imports)

    def hook(event: str, args: tuple[object, ...]) -> None:
        if event == "open":
            path, mode, flags = args
            writes = (
                bool(WRITE_MODE & set(mode))
                if isinstance(mode, str)
                else isinstance(flags, int) and bool(flags & WRITE_FLAGS)
            )
            if writes:
                raise Refused(f"writing files is not allowed ({path!r})")
            if isinstance(path, str | bytes):
                opened.append(os.path.abspath(os.fsdecode(path)))
        elif event in PROCESS_EVENTS:
            raise Refused(f"starting or signalling processes is not allowed ({event})")
        elif event in FILE_EVENTS:
            raise Refused(f"changing files is not allowed ({event})")
        elif event.startswith(REFUSED_PREFIXES):
            raise Refused(f"{event} is not allowed")
        elif event == "import" and not str(args[0]).startswith(allowed):
            raise Refused(f"importing module {args[0]!r} is not allowed")

    sys.addaudithook(hook)
