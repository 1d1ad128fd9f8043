"""Type stubs of the extension module `mx._mx` (re-exported by `mx`)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike]
_Array = npt.ArrayLike

class Interpreter:
    """An mx interpreter; globals persist between `eval` calls.

    steps: limit on each evaluation's steps (None: no limit); root: confine
    load/save to this folder; max_depth: limit on nested mx calls; prelude:
    load stdlib/prelude.mx (shift, stretch, mean, …).
    """

    def __init__(
        self,
        steps: Optional[int] = None,
        root: Optional[_Path] = None,
        max_depth: Optional[int] = None,
        prelude: bool = True,
    ) -> None: ...
    def eval(self, src: str, name: str = "<input>") -> Any:
        """Evaluate mx source; returns the last statement's value. Ctrl-C cancels."""
    def run(self, path: _Path) -> Any:
        """Run an mx script file."""
    def get(self, name: str) -> Any:
        """A global's value; KeyError if unknown."""
    def set(self, name: str, value: Any) -> None:
        """Bind a global (numbers, strings, bools, lists, dicts, arrays, motions, bodies)."""
    def register(self, name: str, fn: Callable[..., Any], doc: Optional[str] = None) -> None:
        """Make a Python callable an mx function (doc defaults to fn.__doc__)."""
    def help(self, name: str) -> Optional[str]:
        """`:help NAME`: signature and doc of a built-in."""
    def names(self) -> List[str]: ...
    def __getitem__(self, name: str) -> Any: ...
    def __setitem__(self, name: str, value: Any) -> None: ...
    def __contains__(self, name: str) -> bool: ...

class Motion:
    """An mx motion: a motion unit (DOF name → DOF), or one DOF."""

    @property
    def dofs(self) -> List[str]:
        """DOF names in first-definition order."""
    @property
    def span(self) -> Optional[Tuple[float, float]]:
        """(start, stop) of everything defined, or None."""
    @property
    def type(self) -> str:
        """`Mu`, `Dof` or `Interval`."""
    def gaps(self) -> List[Tuple[str, float, float]]:
        """Interior gaps as (dof, start, stop)."""
    def conflicts(self) -> List[Tuple[str, float, float]]:
        """Multiply defined stretches as (dof, start, stop)."""
    def sample(self, times: _Array, deriv: int = 0) -> np.ndarray:
        """Array [T, D] at `times`, NaN where undefined (deriv 1, 2: derivatives)."""
    @staticmethod
    def from_array(names: Sequence[str], times: _Array, values: _Array) -> "Motion":
        """A motion from values [T, D] at evenly spaced times; NaN is undefined."""
    def to_dataframe(self, times: Optional[_Array] = None, deriv: int = 0) -> Any:
        """A pandas DataFrame indexed by time (needs pandas)."""
    def frame_times(self) -> List[float]:
        """The motion's frame times (its sample rate, else 30 Hz)."""
    def frames(self) -> int:
        """How many frames the motion has (a loaded clip's frame count)."""
    def frame_time(self) -> float:
        """Seconds per frame (a loaded clip's frame time)."""
    def save(self, path: _Path, **options: Any) -> None:
        """Write by extension: .json, .csv (rate=), .bvh, .glb/.gltf (body=)."""
    def affine(self, ts: float, d: float) -> "Motion":
        """Time t ↦ ts + d·t."""
    def clip(self, ts: float, tf: float) -> "Motion":
        """[ts, tf] moved to start at 0."""
    def clip_in_place(self, ts: float, tf: float) -> "Motion":
        """[ts, tf], times unchanged."""
    def concatenate(self, other: "Motion") -> "Motion":
        """other appended where this one ends."""
    def only(self, *patterns: str) -> "Motion":
        """The DOFs matching any name or glob."""
    def __add__(self, other: "Motion") -> "Motion": ...
    def __sub__(self, other: "Motion") -> "Motion": ...
    def __and__(self, other: "Motion") -> "Motion": ...
    def __len__(self) -> int: ...
    def __contains__(self, name: str) -> bool: ...
    def __getitem__(self, name: str) -> "Motion": ...
    def __getattr__(self, name: str) -> Callable[..., Any]:
        """Any mx function taking a motion first, as a method (`m.shift(0.5)`)."""
    def _repr_html_(self) -> str: ...

class Body:
    """A multibody model (URDF, body_of(clip), human(clip), or mx code)."""

    @staticmethod
    def from_urdf(path: _Path) -> "Body": ...
    @property
    def coordinates(self) -> List[str]: ...
    @property
    def nq(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def mass(self) -> float: ...
    @property
    def links(self) -> List[str]: ...
    @property
    def gravity(self) -> Tuple[float, float, float]: ...
    def inverse_dynamics(self, q: _Array, v: _Array, a: _Array, gravity: Optional[Sequence[float]] = None) -> np.ndarray:
        """τ for one state [nq] or a batch [N, nq] (parallel, GIL released)."""
    def forward_dynamics(self, q: _Array, v: _Array, tau: _Array, gravity: Optional[Sequence[float]] = None) -> np.ndarray:
        """q̈ for one state [nq] or a batch [N, nq]."""
    def mass_matrix(self, q: _Array) -> np.ndarray:
        """M(q): [nq, nq], or [N, nq, nq] for a batch."""
    def positions(self, motion: Motion, rate: Optional[float] = None) -> Dict[str, Any]:
        """Joint positions: {times [T], joints, parents, xyz [T, J, 3]}."""
    def _repr_html_(self) -> str: ...

class Function:
    """An mx function, callable from Python."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any: ...

class Object:
    """Another mx value (joint, scene, …); its fields are attributes."""

    @property
    def type(self) -> str: ...
    def keys(self) -> List[str]:
        """Its field names, as mx's `keys(x)` lists them."""
    def __getattr__(self, name: str) -> Any: ...
    def __dir__(self) -> List[str]: ...

def load(path: _Path, **options: Any) -> Any:
    """A motion, body or value from a file, by extension."""

def body_of(motion: Motion, mass: Optional[float] = None) -> Body:
    """A body whose coordinates are the clip's DOFs."""

def human(motion: Motion, mass: float = 70.0) -> Body:
    """The 44-DOF anatomical model sized from a clip."""

def _sp(motion: Motion, body: Body, options: Optional[Dict[str, Any]] = None, on_tick: Optional[Callable[[float], None]] = None) -> Tuple[Motion, Dict[str, Any]]: ...
def ground_forces(motion: Union[Motion, _Path], body: Optional[Body] = None, friction: float = 0.8, points: Optional[List[str]] = None, floor: Union[float, str, None] = None, height: Optional[float] = None, animation: Union[str, int, None] = None) -> Dict[str, Any]:
    """The contact forces per point and the residual per frame, as NumPy arrays (or those a glTF file carries, given its path and no body)."""

def _doc(name: str) -> Optional[str]: ...
def _builtins() -> List[Tuple[str, str, str]]: ...
