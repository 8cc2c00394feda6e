"""How the simulation loop is compiled: once per line structure, with no reference counting.

Both are performance properties (see ``webline.sim.elements.layout`` and
``webline.sim.elements.signals``) that
a harmless-looking edit could silently undo, so they are checked directly.
"""

from __future__ import annotations

import re

import numba as nb

import webline
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan, equilibrium_plan_state
from webline.sim.elements.signals import _NO_NRT, FAST


def test_a_parameter_change_reuses_the_compiled_loop(hswl):
    """Tension, speed, inertia and gains are run-time parameters: no new compile for them."""
    other = hswl.replace(speed="800 ft/min").replace(
        web={**hswl.spec.web.model_dump(), "thickness": 2 * hswl.spec.web.thickness})
    assert compile_plan(other).web[webline.sim.elements.layout.W_THICK] != compile_plan(
        hswl).web[webline.sim.elements.layout.W_THICK]
    assert kernel.compiled_loop(compile_plan(other)) is kernel.compiled_loop(compile_plan(hswl))


def test_a_structure_change_compiles_another_loop(hswl):
    """A brake adds a drag profile to a node: a different structure, a different loop."""
    braked = hswl.replace(disturbances=[{"type": "roller_drag", "roller": "idler",
                                         "torque": "0.1 N*m"}])
    assert kernel.compiled_loop(compile_plan(braked)) is not kernel.compiled_loop(
        compile_plan(hswl))


def test_the_loop_makes_no_reference_counting_call(hswl, monkeypatch):
    """Compiled afresh (cached code cannot be inspected), the loop's LLVM IR calls neither
    NRT_incref nor NRT_decref: each would be an atomic operation in the inner loop."""
    plan = compile_plan(hswl)
    fresh = nb.njit(fastmath=FAST, error_model="numpy", **_NO_NRT)(
        kernel.compiled_loop(plan).py_func)
    monkeypatch.setattr(kernel, "compiled_loop", lambda _: fresh)
    x0, istate0 = equilibrium_plan_state(plan)
    kernel.run(plan, x0, istate0, kernel.initial_slip(plan, x0), 0, 10, 1, 1, True)
    ir = fresh.inspect_llvm(fresh.signatures[0])
    calls = set(re.findall(r"call [^@]*@(NRT_\w+)", ir))
    assert not calls & {"NRT_incref", "NRT_decref"}, calls
