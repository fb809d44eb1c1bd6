"""What a child process that runs an untrusted file does to itself first (see ``docs/security.md``).

Five layers, each one holding if the others are got round:

* :func:`limit`: resource limits: address space and CPU time bounded, no file may grow (so none
  is written), no new process for an ordinary user (``RLIMIT_NPROC`` 0; the kernel does not apply
  it to root, whom the next layer stops), no core file;
* :func:`die_with_parent`: the process is killed the moment the process that started it ends,
  even by ``SIGKILL``;
* :func:`forbid_syscalls`: a seccomp filter (Linux on x86-64 and AArch64) makes the kernel refuse
  the system calls that start a program or a process, signal or trace another process, open a
  socket, or create, change or remove a file; they fail with ``EPERM``, for root too, from Python
  or from machine code alike;
* :func:`restrict_reading`: Linux's Landlock (kernel 5.13 on) makes the kernel refuse, with
  ``EACCES``, to open, list or run any file but those beneath the directories (and the files)
  it is given, and to write, make or remove any file at all, from Python or machine code alike;
* :func:`guard`: a Python audit hook (PEP 578) refuses the same in Python (processes, signals,
  sockets, writing or changing files, ``ctypes``, importing a module not yet imported, the
  introspection attributes that reach frames and code) and records every file the process opens.

Only the standard library is used: this module runs in a child started in isolated mode, whose
``sys.path`` is the standard library's (and it is imported from its file, not as part of urdf2dh).
"""

from __future__ import annotations

import os
import platform
import stat
import struct
import sys
from collections.abc import Callable, Iterable

__all__ = ["Refused", "die_with_parent", "forbid_syscalls", "guard", "limit", "restrict_reading"]


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


def _libc_function(name: str) -> Callable[..., int] | None:
    """The C library's function ``name`` (Linux only), setting ``errno`` for :func:`_os_error`."""
    if not sys.platform.startswith("linux"):
        return None
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None
    function: Callable[..., int] = getattr(libc, name)
    return function


def _prctl() -> Callable[..., int] | None:
    return _libc_function("prctl")


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


# --------------------------------------------------------------------------- Landlock

# <linux/landlock.h>: system call numbers (the same on every architecture that has them), the
# file system rights and the ABI version that first knows each, the network and scope rights.
LANDLOCK_CALLS = {"create_ruleset": 444, "add_rule": 445, "restrict_self": 446}
LANDLOCK_CREATE_RULESET_VERSION = 1
LANDLOCK_RULE_PATH_BENEATH = 1
FS_EXECUTE, FS_WRITE_FILE, FS_READ_FILE, FS_READ_DIR = 1 << 0, 1 << 1, 1 << 2, 1 << 3
FS_RIGHTS_SINCE = {  # ABI -> the file system rights it added
    1: (1 << 13) - 1,  # EXECUTE ... MAKE_SYM: run, write, read, list, make and remove files
    2: 1 << 13,  # REFER: link or rename a file into another directory
    3: 1 << 14,  # TRUNCATE
    5: 1 << 15,  # IOCTL_DEV: ioctl on a device
}
FILE_RIGHTS = FS_EXECUTE | FS_WRITE_FILE | FS_READ_FILE | 1 << 14 | 1 << 15  # rights of a file
NET_RIGHTS = (1 << 0) | (1 << 1), 4  # BIND_TCP | CONNECT_TCP, from ABI 4
SCOPES = (1 << 0) | (1 << 1), 6  # ABSTRACT_UNIX_SOCKET | SIGNAL, from ABI 6


def landlock_abi() -> int:
    """The Landlock ABI version the running kernel offers; 0 where there is none (not Linux,
    a kernel before 5.13 or built without it, Landlock switched off, the call refused)."""
    return _landlock_version(_libc_function("syscall"))


def _landlock_version(syscall: Callable[..., int] | None) -> int:
    if syscall is None:
        return 0
    version = syscall(LANDLOCK_CALLS["create_ruleset"], None, 0, LANDLOCK_CREATE_RULESET_VERSION)
    return max(int(version), 0)


def restrict_reading(trees: Iterable[str], files: Iterable[str] = ()) -> int:
    """Let this process, from now on, read only beneath the directories ``trees`` and the files
    ``files`` (paths the kernel resolves, symbolic links followed), and write, make or remove no
    file; the Landlock ABI version applied, 0 where Landlock is not available (nothing changed).

    Every file system right the running kernel knows is handled; beneath ``trees`` a file may
    be read and a directory listed, ``files`` may be read; nothing else is allowed. From ABI 4
    TCP ``bind``/``connect`` are refused too, from ABI 6 abstract Unix sockets and signals
    to processes outside. A path that does not exist is left out.

    Raises
    ------
    OSError
        Landlock is there but refused the rules (the process is then not restricted).
    """
    syscall = _libc_function("syscall")
    abi = _landlock_version(syscall)
    prctl = _prctl()
    if abi < 1 or syscall is None or prctl is None:
        return 0
    handled = sum(rights for since, rights in FS_RIGHTS_SINCE.items() if since <= abi)
    fields = [handled]
    if abi >= NET_RIGHTS[1]:
        fields.append(NET_RIGHTS[0])
    if abi >= SCOPES[1]:
        fields.append(SCOPES[0])
    # struct landlock_ruleset_attr, as long as this ABI has it (a longer one would be refused)
    attr = struct.pack(f"={len(fields)}Q", *fields)
    ruleset = syscall(LANDLOCK_CALLS["create_ruleset"], attr, len(attr), 0)
    if ruleset < 0:
        raise _os_error("landlock_create_ruleset")
    try:
        rules = [(t, FS_READ_FILE | FS_READ_DIR) for t in trees] + [
            (f, FS_READ_FILE) for f in files
        ]
        for path, allowed in rules:
            _add_rule(syscall, ruleset, path, allowed & handled)
        if prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
            raise _os_error("prctl(PR_SET_NO_NEW_PRIVS)")
        if syscall(LANDLOCK_CALLS["restrict_self"], ruleset, 0) != 0:
            raise _os_error("landlock_restrict_self")
    finally:
        os.close(ruleset)
    return abi


def _add_rule(syscall: Callable[..., int], ruleset: int, path: str, allowed: int) -> None:
    try:
        fd = os.open(path, os.O_PATH | os.O_CLOEXEC)
    except FileNotFoundError:
        return
    try:
        if not stat.S_ISDIR(os.fstat(fd).st_mode):
            allowed &= FILE_RIGHTS  # a file takes a file's rights only
        rule = struct.pack("=Qi", allowed, fd)  # struct landlock_path_beneath_attr (packed)
        if syscall(LANDLOCK_CALLS["add_rule"], ruleset, LANDLOCK_RULE_PATH_BENEATH, rule, 0) != 0:
            raise _os_error(f"landlock_add_rule({path})")
    finally:
        os.close(fd)


def _os_error(call: str) -> OSError:
    import ctypes

    number = ctypes.get_errno()
    return OSError(number, f"{call}: {os.strerror(number)}")


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
