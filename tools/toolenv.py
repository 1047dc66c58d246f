"""toolenv: what the Python tools of tools/ (compare, reference, chart) do before importing their
packages. They run in the repository's .venv when it exists (tools/setup-python makes it from
tools/requirements.txt), so `tools/chart ...` works from any shell; and Dr.Jit, under Mitsuba's
LLVM variant, gets an LLVM it can use: Debian 12's own LLVM 15 cannot compile what Dr.Jit 1.x
emits ("Cannot select: fminimum"), so the newest libLLVM-N.so with N >= 16 is chosen
(tools/setup-python installs libllvm19)."""
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VENV = os.path.join(ROOT, ".venv")
OLDEST_LLVM = 16


def enter_venv():
    """Re-runs this script with .venv's Python unless it already runs there (or there is none)."""
    python = os.path.join(VENV, "bin", "python")
    if os.path.exists(python) and os.path.realpath(sys.prefix) != os.path.realpath(VENV):
        os.execv(python, [python] + sys.argv)


def find_llvm():
    """Sets DRJIT_LIBLLVM_PATH to the newest usable libLLVM unless it is set already; returns it."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return os.environ["DRJIT_LIBLLVM_PATH"]
    found = []
    for path in glob.glob("/usr/lib/*/libLLVM-*.so") + glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so"):
        m = re.search(r"LLVM-(\d+)\.so$", path) or re.search(r"llvm-(\d+)/", path)
        if m and int(m.group(1)) >= OLDEST_LLVM:
            found.append((int(m.group(1)), path))
    if not found:
        return None
    os.environ["DRJIT_LIBLLVM_PATH"] = max(found)[1]
    return os.environ["DRJIT_LIBLLVM_PATH"]


def need(module, what):
    """Imports module or stops with a message saying how to install the tools' packages."""
    try:
        return __import__(module)
    except ImportError:
        sys.exit(f"{os.path.basename(sys.argv[0])}: needs {what} (Python package '{module}'); "
                 f"run tools/setup-python, which makes .venv from tools/requirements.txt")
