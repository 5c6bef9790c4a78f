"""``shaped(a, shape)``: ``a.reshape(shape)`` in compiled kernels without Numba's run-time reshape call.

Numba compiles ``a.reshape(shape)`` into a call of its C helper ``numba_attempt_nocopy_reshape`` (it works out
whether any array's memory allows the new shape without a copy), ~8 ns a call. The one-call IK kernels
(:mod:`armkit.ik.analytic._single`) cut ~20 pieces of their work vectors into the shapes the family kernels take
for every target: ``perf`` put that helper at 5 % of a Puma 560 call, and removing the calls took a quarter of the
call (each was a point past which the compiler reloaded what it held). :func:`shaped` writes the view's shape and
strides directly, which it can for the two kinds of array the kernels hand it:

* a 1-D array (any stride ``s``: element ``(i0, ..., ik)`` of the C-order view is element
  ``i0 d1...dk + ... + ik`` of ``a``, so the view's strides are ``s`` times the C-order multipliers), the pieces
  ``w[a:b]`` of a work vector;
* an array whose type says C-contiguous (strides from the item size).

Its total size must be the array's (else ``ValueError``, as ``reshape``). A Numba intrinsic: it runs in compiled
code only (the kernels that call it are never run as Python). Numba is imported here: load this module only where
Numba is.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.core.extending import intrinsic
from numba.core.imputils import impl_ret_borrowed
from numba.np.arrayobj import make_array, populate_array

__all__ = ["shaped"]


@intrinsic
def shaped(typingctx, a, shape):  # (no annotations: Numba compares the signatures of what it compiles)
    if not _takes(a, shape):
        return None
    nd = len(shape)
    ret = a.copy(ndim=nd, layout="C" if a.layout == "C" else "A")

    def codegen(context, builder, sig, args):
        aryty = sig.args[0]
        ary = make_array(aryty)(context, builder, args[0])
        dims = [context.cast(builder, d, t, types.intp)
                for d, t in zip(cgutils.unpack_tuple(builder, args[1], nd), sig.args[1])]
        total = context.get_constant(types.intp, 1)
        for d in dims:
            total = builder.mul(total, d)
        with cgutils.if_unlikely(builder, builder.icmp_signed("!=", total, ary.nitems)):
            context.call_conv.return_user_exc(builder, ValueError, ("total size of new array must be unchanged",))
        if aryty.ndim == 1:   # any stride s: the C-order multipliers times s
            step = cgutils.unpack_tuple(builder, ary.strides, 1)[0]
        else:
            step = ary.itemsize
        strides = [step] * nd
        for k in range(nd - 2, -1, -1):
            strides[k] = builder.mul(strides[k + 1], dims[k + 1])
        out = make_array(sig.return_type)(context, builder)
        populate_array(out, data=ary.data, shape=dims, strides=strides, itemsize=ary.itemsize,
                       meminfo=ary.meminfo, parent=ary.parent)
        return impl_ret_borrowed(context, builder, sig.return_type, out._getvalue())

    return ret(a, shape), codegen


def _takes(a, shape):
    """Whether :func:`shaped` takes these types: an array 1-D or C-contiguous, a tuple of integers."""
    return isinstance(a, types.Array) and (a.ndim == 1 or a.layout == "C") and isinstance(shape, types.BaseTuple) \
        and len(shape) > 0 and all(isinstance(t, types.Integer) for t in shape)
