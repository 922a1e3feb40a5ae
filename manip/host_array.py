"""Result arrays that also answer torch's host-side calls, as cuRobo's results do.

cuRobo's results hold torch tensors, and scripts written for it read them with
`result.success.item()`, `result.success.cpu().numpy()` or `.tolist()`. manip's results hold
NumPy values; `HostArray` is a read-only `np.ndarray` that also has torch's `cpu()`,
`numpy()`, `detach()` and `clone()` (all on the host: no copy), so those lines run as written.
A result of one problem holds a batch of one, as cuRobo's does: `success` of one plan is (1,)
(`result.success[0]`, `.item()`, `bool()`, `if result.success:`), of one IK solution (1, 1).
As on a torch tensor, a one-element `HostArray` converts with `float()` / `int()` and formats
(`f"{result.position_error:.3f}"`) as the number it holds (NumPy refuses both for ndim > 0).
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError


class HostArray(np.ndarray):
    """A read-only NumPy array with torch's host-side methods (`cpu`, `numpy`, `detach`, `clone`)."""

    def cpu(self) -> HostArray:
        """Itself (torch's copy to the host: manip's arrays are there already)."""
        return self

    def detach(self) -> HostArray:
        """Itself (nothing to detach: no autograd)."""
        return self

    def clone(self) -> HostArray:
        """Itself (read-only, so sharing is safe)."""
        return self

    def numpy(self) -> np.ndarray:
        """The values as a plain (read-only) `np.ndarray`."""
        return self.view(np.ndarray)

    def cuda(self, *args, **kwargs):
        """Refused: manip runs on the CPU."""
        raise InvalidInputError("manip's results live on the CPU (no CUDA): drop `.cuda()` (`.cpu()` is accepted)")

    def to(self, *args, **kwargs):
        """torch's `to(device)`: only the CPU is accepted (the array itself)."""
        device = args[0] if args else kwargs.get("device", "cpu")
        if str(device).split(":")[0] != "cpu":
            raise InvalidInputError(f"manip's results live on the CPU; got .to({device!r}): use .to('cpu') or drop it")
        return self

    def _one(self, what: str):
        if self.size != 1:
            raise TypeError(f"only one-element arrays convert to {what}; this one has shape {self.shape}")
        return self.item()

    def __float__(self) -> float:
        return float(self._one("float"))

    def __int__(self) -> int:
        return int(self._one("int"))

    def __complex__(self) -> complex:
        return complex(self._one("complex"))

    def __format__(self, spec: str) -> str:
        return format(self.item(), spec) if self.size == 1 else super().__format__(spec)

    def __repr__(self) -> str:
        return repr(self.item()) if self.ndim == 0 else super().__repr__()

    def __str__(self) -> str:
        return str(self.item()) if self.ndim == 0 else super().__str__()

    def __hash__(self) -> int:
        if self.ndim:
            raise TypeError("unhashable type: 'HostArray' (an array; its 0-d scalars hash)")
        return hash(self.item())


def host(value, dtype=None, shape: tuple | None = None) -> HostArray:
    """`value` (a scalar or an array) as a read-only `HostArray` (a copy only when needed);
    `shape` reshapes it (a result of one problem: (1,) for a plan, (1, 1) for an IK solution)."""
    a = np.array(value, dtype=dtype) if np.ndim(value) == 0 else np.asarray(value, dtype=dtype)
    if shape is not None:
        a = a.reshape(shape)
    out = a.view(HostArray)
    out.setflags(write=False)
    return out
