"""The project's version for the Python tools' --version: CMakeLists.txt's project() (written once)."""
import os
import re


def version():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "CMakeLists.txt")
    with open(path) as f:
        m = re.search(r"^project\(hullgrind VERSION ([0-9.]+)", f.read(), re.M)
    return m.group(1) if m else "unknown"
