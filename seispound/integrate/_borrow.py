"""Borrowed arrays: views without a reference count, for the kernel's time loop.

numba counts references to every array it allocates or receives (a *meminfo*
per buffer): each new alias, view or argument of a call increments the count
and decrements it again when it dies, both with atomic instructions.  numba's
pruning pass removes the pairs it can prove redundant, but in a loop of the
kernel's size many stay: 313 000 calls in the first 10 s of the canonical row
(about 150 per analysis step, counted with a debugger breakpoint on numba's
``NRT_incref`` and ``NRT_decref``), 13 % of the samples of
``python -m benchmarks.profile_kernel``.  Borrowed, 31 000 calls remain, each a
test of a null pointer, and the run is 7-10 % faster (same-process A/B).

:func:`borrow` returns the same array (data, shape, strides) with no meminfo,
so every reference-count operation on it, on its aliases and on its views is a
test of a null pointer.  The caller must keep the owner alive for as long as
the borrowed array is used: the kernel borrows its arguments (alive for the
whole call) and the work arrays it allocates, which it holds in a tuple passed
to :func:`keep_alive` at its end.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.core.extending import _Intrinsic


class _WithPythonForm(_Intrinsic):
    """``numba.extending.intrinsic`` whose call from Python runs its Python form (``_PYTHON``) instead of raising:
    the kernel run as Python (:mod:`seispound._first_use`, ``NUMBA_DISABLE_JIT``) has no counts to skip."""

    def __call__(self, *args, **kwargs):
        return _PYTHON[self._name](*args, **kwargs)


def _intrinsic(defn):
    made = _WithPythonForm(defn.__name__, defn)
    made._register()
    return made


_PYTHON = {"borrow": lambda arr: arr, "borrow_all": lambda group: group, "keep_alive": lambda owners: None}


@_intrinsic
def borrow(typingctx, arr):
    """The array ``arr`` without its reference count (same type, data, shape and strides)."""
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        return _borrowed(context, builder, arr, args[0])

    return arr(arr), codegen


@_intrinsic
def keep_alive(typingctx, owners):
    """Do nothing with ``owners``: a use that keeps them (and what they own) alive up to here."""

    def codegen(context, builder, signature, args):
        return context.get_dummy_value()

    return types.none(owners), codegen


def _borrowed(context, builder, typ, value):
    """``value`` of type ``typ`` with every array in it borrowed (tuples recursively; scalars as they are)."""
    if isinstance(typ, types.Array):
        src = context.make_array(typ)(context, builder, value=value)
        dst = context.make_array(typ)(context, builder)
        dst.meminfo = cgutils.get_null_value(dst.meminfo.type)
        dst.parent = cgutils.get_null_value(dst.parent.type)
        dst.nitems = src.nitems
        dst.itemsize = src.itemsize
        dst.data = src.data
        dst.shape = src.shape
        dst.strides = src.strides
        return dst._getvalue()
    if isinstance(typ, types.BaseTuple):
        out = value
        for k, member in enumerate(typ):
            out = builder.insert_value(out, _borrowed(context, builder, member, builder.extract_value(value, k)), k)
        return out
    return value


@_intrinsic
def borrow_all(typingctx, group):
    """The tuple ``group`` (nested or not) with every array in it borrowed: a named group of the kernel's
    arrays (same types, data, shapes and strides; scalars as they are)."""
    if not isinstance(group, types.BaseTuple):
        return None

    def codegen(context, builder, signature, args):
        return _borrowed(context, builder, group, args[0])

    return group(group), codegen
