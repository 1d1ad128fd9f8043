"""mx from Python: motion expressions, motion algebra and multibody dynamics.

>>> import mx, numpy as np
>>> clip = mx.load("walk.bvh")                  # an mx.Motion
>>> arr = clip.sample(np.arange(0, 2, 1 / 30))  # ndarray [T, D], NaN where undefined
>>> body = mx.body_of(clip)                      # an mx.Body
>>> tau = body.inverse_dynamics(q, v, a)         # q, v, a: [nq] or a batch [N, nq]

The interpreter: ``mx.Interpreter(steps=..., root=...)`` with ``.eval``,
``.run``, ``.get``, ``.set`` and ``.register(name, fn, doc)``. Errors are
:class:`mx.MxError` subclasses carrying the rendered diagnostic.
"""

import os
from typing import Any, Dict, List, Optional, Tuple, Union

from . import _mx
from ._errors import (
    MxCancelledError,
    MxError,
    MxIOError,
    MxLimitError,
    MxMotionError,
    MxNameError,
    MxSyntaxError,
    MxTypeError,
    MxValueError,
)
from ._mx import Body, Function, Interpreter, Motion, Object

__all__ = [
    "Body",
    "Function",
    "Interpreter",
    "Motion",
    "Object",
    "MxError",
    "MxSyntaxError",
    "MxNameError",
    "MxTypeError",
    "MxValueError",
    "MxMotionError",
    "MxIOError",
    "MxLimitError",
    "MxCancelledError",
    "body_of",
    "ground_forces",
    "human",
    "load",
    "sp",
    "help_text",
]

__version__ = "0.1.0"


def sp(motion: Motion, body: Body, progress: Optional[bool] = None, **options: Any) -> Tuple[Motion, Dict[str, Any]]:
    """Fill every interior gap of ``motion`` with a spacetime transition.

    Returns ``(filled_motion, report)``; the report is a dict with every field
    of mx's ``sp_report`` (``groups``, ``root``, ``pinned``, ``contacts``,
    ``hermite``, ``constant``, ``undefined``, ``text``). Options are those of mx's
    ``SP`` (below). A tqdm bar shows the elapsed time after half a second when
    tqdm is installed (``progress=False`` hides it). Ctrl-C cancels the solve
    and raises KeyboardInterrupt.
    """
    bar = None
    tick = None
    if progress is not False:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            tqdm = None
        if tqdm is not None:
            state = {"bar": None, "last": 0.0}

            def tick(seconds: float) -> None:
                if seconds < 0.5:
                    return
                if state["bar"] is None:
                    state["bar"] = tqdm(desc="SP", unit="s", bar_format="{desc}: {elapsed} {postfix}")
                state["bar"].update(seconds - state["last"])
                state["last"] = seconds

            bar = state
    try:
        return _mx._sp(motion, body, options, tick)
    finally:
        if bar is not None and bar["bar"] is not None:
            bar["bar"].close()


def load(path, **options: Any) -> Any:
    """A motion, a body or another value from a file, chosen by its extension."""
    return _mx.load(path, **options)


def body_of(motion: Motion, mass: Optional[float] = None) -> Body:
    """A body whose coordinates are exactly the clip's DOFs (70 kg by default,
    or the saved body of a glTF file mx wrote)."""
    return _mx.body_of(motion, mass)


def human(motion: Motion, mass: float = 70.0) -> Body:
    """The 44-DOF anatomical model with limb lengths from the clip's skeleton."""
    return _mx.human(motion, mass)


def ground_forces(
    motion: Union[Motion, str, "os.PathLike[str]"],
    body: Optional[Body] = None,
    friction: float = 0.8,
    points: Optional[List[str]] = None,
    floor: Union[float, str, None] = None,
    height: Optional[float] = None,
    animation: Union[str, int, None] = None,
) -> Dict[str, Any]:
    """Per frame, the contact forces that best hold ``body`` up and what they leave.

    Returns a dict of NumPy arrays: ``times`` [T], ``points`` (names),
    ``forces`` [T, P, 3] (N, world axes; zero off the floor), ``in_contact``
    [T, P], ``residual_force`` [T, 3] (N), ``residual_moment`` [T, 3] (N·m
    about the centre of mass), ``percent_bw`` [T] (the residual force as % of
    body weight), ``com`` [T, 3] (m), and ``weight`` (N) and ``floor`` (m).
    The numbers of mx's ``ground_forces`` (below), from the same solve.

    ``ground_forces("walk.glb", animation=None)``, without a body: the forces
    a glTF file carries (``save(m, "walk.glb", body: b, forces: true)``), on
    the animation's frames from 0 s, number for number as they were saved:
    ``times``, ``points``, ``forces``, ``residual_force``,
    ``residual_moment``, ``percent_bw``, and ``up`` (the saved body's up, in
    the file's axes) and ``animation`` (its name). ``mx.load("walk.glb",
    forces=True)`` gives the same numbers as an mx.Motion.
    """
    return _mx.ground_forces(motion, body, friction, points, floor, height, animation)


def help_text(name: str) -> Optional[str]:
    """The ``:help NAME`` text of an mx built-in (None if unknown)."""
    return _mx._doc(name)


def _with_mx_doc(f, mx_name: str, intro: str) -> None:
    doc = _mx._doc(mx_name)
    if doc:
        f.__doc__ = (intro.rstrip() + "\n\nmx's own documentation:\n\n" + doc).strip()


_with_mx_doc(sp, "SP", sp.__doc__ or "")
_with_mx_doc(load, "load", load.__doc__ or "")
_with_mx_doc(body_of, "body_of", body_of.__doc__ or "")
_with_mx_doc(human, "human", human.__doc__ or "")
_with_mx_doc(ground_forces, "ground_forces", ground_forces.__doc__ or "")
