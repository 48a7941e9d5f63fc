"""Type stubs of the granular_automata module (python/src/lib.rs)."""

from typing import Any, Callable, Optional

import numpy as np
import numpy.typing as npt

__version__: str

class Pipe:
    """One run of the pipe lattice gas (MODEL.md Part A)."""

    def __init__(
        self,
        width: int = 11,
        length: int = 220,
        rho: float = 1.0,
        p: float = 0.5,
        g: float = 0.5,
        b: float = 0.5,
        bin: int = 10,
        boundary: str = "periodic",
        inject: Optional[float] = None,
        rules: str = "default",
        seed: int = 1,
        engine: str = "reference",
    ) -> None: ...
    def step(self) -> None: ...
    def run(self, steps: int) -> None: ...
    @property
    def time(self) -> int: ...
    @property
    def params(self) -> dict[str, Any]: ...
    @property
    def rules(self) -> str: ...
    @property
    def engine(self) -> str: ...
    def state(self) -> npt.NDArray[np.uint8]: ...
    def set_state(self, state: npt.NDArray[np.uint8]) -> None: ...
    def site(self, x: int, y: int) -> int: ...
    def set_site(self, x: int, y: int, state: int) -> None: ...
    def bin_counts(self) -> npt.NDArray[np.float64]: ...
    def channel_counts(self) -> npt.NDArray[np.uint64]: ...
    def flux(self) -> tuple[int, int, int]: ...
    def particle_count(self) -> int: ...
    def set_p(self, p: float) -> None: ...

class Hopper:
    """One run of the hopper automaton (MODEL.md Part B)."""

    def __init__(self, params: Optional[str] = None, seed: int = 1) -> None: ...
    @staticmethod
    def default_params() -> str: ...
    def step(self, rain: bool = False) -> tuple[int, int, int, int]: ...
    def open(self) -> None: ...
    def fill(self, target: int, max_iterations: int = 1_000_000, max_settle: int = 10_000) -> int: ...
    def sites(self) -> npt.NDArray[np.uint8]: ...
    def grains(self) -> int: ...
    @property
    def iteration(self) -> int: ...

def bin_series(
    seed: int,
    tier: str = "quick",
    rules: str = "default",
    engine: str = "reference",
    p: float = 0.5,
    g: float = 0.5,
    b: float = 0.5,
    rho: float = 1.0,
    width: int = 11,
    length: int = 220,
) -> npt.NDArray[np.float64]: ...
def spectrum_ensemble(
    tier: str = "quick",
    seed: int = 1,
    runs: Optional[int] = None,
    rules: str = "default",
    engine: Optional[str] = None,
    threads: Optional[int] = None,
    p: float = 0.5,
    g: float = 0.5,
    b: float = 0.5,
    rho: float = 1.0,
    width: int = 11,
    length: int = 220,
) -> dict[str, Any]: ...
def spectrum(
    series: npt.NDArray[np.float64], m: int = 16384, k: int = 4, window: str = "parzen"
) -> npt.NDArray[np.float64]: ...
def fit_alpha(spectrum: npt.NDArray[np.float64]) -> dict[str, float]: ...
def grade(
    mean: float,
    se: float,
    n: int,
    target: Optional[float] = None,
    margin: Optional[float] = None,
    above: Optional[float] = None,
    below: Optional[float] = None,
) -> str: ...
def claims() -> tuple[list[tuple[str, str]], list[dict[str, Any]]]: ...
def validate(
    candidate: str | Callable[[dict[str, Any], str, int], Any],
    level: str = "1",
    tier: str = "quick",
    rules: str = "default",
    seed: int = 1,
    name: str = "python",
) -> dict[str, Any]: ...
