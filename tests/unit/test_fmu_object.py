"""The FMU's loop object (``webline.fmu.loop_object.compile_object``): a module that needs
only libm compiles to a position-independent object exporting ``webline_loop`` alone; one that
needs Python's C API or numba's runtime is refused, naming what it needs."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from webline.fmu.loop_object import ENTRY, FmuBuildError, compile_object

MODULE = """
declare double @sin(double)
declare void @{extra}(ptr)
define internal double @helper(double %x) {{
  %y = call double @sin(double %x)
  ret double %y
}}
define linkonce_odr void @unused(ptr %p) {{
  call void @{extra}(ptr %p)
  ret void
}}
define i32 @webline_loop(ptr %out, double %x) {{
  %y = call double @helper(double %x)
  {call}
  store double %y, ptr %out
  ret i32 0
}}
"""


def test_only_libm_and_one_entry_point(tmp_path: Path) -> None:
    # (numba leaves helpers like NRT_decref defined but unused: they are dropped, so the
    # runtime they would call is not needed)
    obj = compile_object(MODULE.format(extra="NRT_MemInfo_call_dtor", call=""))
    path = tmp_path / "loop.o"
    path.write_bytes(obj)
    symbols = subprocess.run(["nm", str(path)], capture_output=True, text=True,
                             check=True).stdout.split("\n")
    undefined = {s.split()[-1] for s in symbols if " U " in s}
    exported = {s.split()[-1] for s in symbols if " T " in s or " W " in s}
    assert undefined == {"sin"}
    assert exported == {ENTRY}


def test_a_loop_that_needs_python_is_refused() -> None:
    with pytest.raises(FmuBuildError, match=r"PyErr_SetNone.*beyond libm"):
        compile_object(MODULE.format(extra="PyErr_SetNone",
                                     call="call void @PyErr_SetNone(ptr %out)"))
