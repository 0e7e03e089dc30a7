"""FMPy for a test, from the source folder $PCS_FMPY_SRC names (FMPy is not a
dependency of this project: it is fetched and built outside the repository)."""
import os
import sys
from pathlib import Path


def fmpy_source():
    """The folder holding the `fmpy` package, importable from this process;
    None after printing why the test is skipped (unset, or FMPy does not
    import: a missing lxml or attrs)."""
    src = os.environ.get("PCS_FMPY_SRC")
    if not src or not (Path(src) / "fmpy").is_dir():
        print("skipped: set PCS_FMPY_SRC to FMPy's source folder (the one holding fmpy/) to run this test")
        return None
    sys.path.insert(0, src)
    try:
        import fmpy  # noqa: F401
    except Exception as e:
        print(f"skipped: FMPy does not import ({e}); Debian: python3-lxml python3-attr")
        return None
    return src
