"""Linear solves of the stitching: one sparse factorisation per solve, the seam vertices'
block of its inverse, and the small Schur-complement systems of the seam constraints."""

from __future__ import annotations

import contextvars
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ptailor import tolerances as tol
from ptailor.method.ease import SeamEase


@dataclass(eq=False)
class _Symbolic:
    """One CHOLMOD analysis: the pattern it is for, the matrix and factor objects, and the
    factorisation whose values the factor holds now."""

    indptr: np.ndarray
    indices: np.ndarray
    S: object  # cvxopt.spmatrix, lower triangle
    F: object  # cvxopt CHOLMOD factor
    owner: object = None
    perm: np.ndarray | None = None  # the ordering asked for (None: CHOLMOD's choice)


#: the analyses shared within :func:`shared_symbolic` (per thread and task: a context
#: variable, so garments run in threads of one process, as a Dask worker does, never see
#: each other's)
_SHARED: contextvars.ContextVar[list[_Symbolic] | None] = contextvars.ContextVar(
    "ptailor_shared_symbolic", default=None
)
#: ``cvxopt.cholmod.options`` is one dict per process: an analysis sets it, calls CHOLMOD
#: and restores it under this lock, so a concurrent analysis never runs with its options
_OPTIONS = threading.Lock()


@contextmanager
def shared_symbolic() -> Iterator[None]:
    """Within the block, factorisations of matrices with one sparsity pattern share one
    symbolic analysis (ordering, supernodes): the uniform baseline's matrix has ours'
    pattern, so it costs only its numeric factorisation. Solves stay exact: a solve whose
    factor was overwritten by a later factorisation refactors its own values first."""
    token = _SHARED.set([])
    try:
        yield
    finally:
        _SHARED.reset(token)


def _finite(A: sp.csc_matrix) -> None:
    from ptailor.errors import PtailorError

    if not np.all(np.isfinite(A.data)):
        raise PtailorError(
            "flatten: the stitching matrix has non-finite entries (degenerate target "
            "triangles or extreme flatten weights)"
        )


def factor(A: sp.spmatrix, *, lower: bool = False):
    """Factor a sparse symmetric positive definite matrix once; return a solve function.

    A supernodal Cholesky factorisation (CHOLMOD, from cvxopt) of the lower triangle; its
    fill is about half of an LU's and it factors 1.5-3 times faster. Explicit zeros count
    as pattern (the symbolic analysis is shared by pattern, :func:`shared_symbolic`).
    Without cvxopt, or when the matrix is not positive definite to working precision,
    SuperLU factors it (the second names a singular matrix as before).

    Parameters
    ----------
    A : (N, N) sparse matrix
        Symmetric (only its lower triangle is read by CHOLMOD).
    lower : bool
        ``A`` holds only the lower triangle of the symmetric matrix.

    Returns
    -------
    callable
        ``b (N,) or (N, c) -> A^-1 b`` of the same shape.

    Raises
    ------
    PtailorError
        Non-finite entries, or a matrix SuperLU finds singular.
    """
    A = sp.csc_matrix(A)
    _finite(A)
    try:
        from cvxopt import cholmod  # noqa: F401 - present, or SuperLU
    except ImportError:  # pragma: no cover - cvxopt is a dependency
        return _superlu(A, lower=lower)
    try:
        # one factorisation per connected block of the graph (each panel, and each
        # coordinate where the as-similar-as-possible rows leave x and y apart; the unused
        # vertices together): the same fill as one, smaller analyses (at 300,000 triangles
        # 166 MB of factors instead of 222, 10 % less time)
        return SeamFactor(A if lower else sp.tril(A, format="csc"), np.zeros(0, dtype=np.int64))
    except ArithmeticError:  # not positive definite numerically: LU decides
        return _superlu(A, lower=lower)


class SeamFactor:
    """``A^-1`` from CHOLMOD factors that eliminate the seam unknowns last, so that the
    seam step's two solves cost about one.

    The matrix is factored per connected block (:func:`factor`'s blocks; equal blocks
    once, solved together), each in AMD's order with its seam unknowns moved to the end:
    ``P A P^T = L L^T`` with the trailing block ``T`` of ``L`` the Cholesky factor of the
    Schur complement onto the seam unknowns. Then ``A^-1`` restricted to them is
    ``T^-T T^-1`` (:meth:`blocks`), the seam values of ``A^-1 b`` follow from the forward
    substitution ``z = L^-1 P b`` by ``T^-T z_s`` (:meth:`seam_values`), and
    ``A^-1 (b - E w)`` for ``w`` on the seam unknowns from the same ``z`` by
    ``z_s -= T^-1 w`` and one back-substitution (:meth:`finish`): the constrained step
    ``x = A^-1 b - A^-1 C^T nu`` with ``nu`` from ``C A^-1 b`` takes one forward and one
    back-substitution instead of two of each.

    Parameters
    ----------
    L : (N, N) sparse matrix
        Lower triangle of the symmetric positive definite matrix.
    last : (s,) int array
        The seam unknowns (distinct), in the order :meth:`seam_values` uses.

    Raises
    ------
    ArithmeticError
        A block is not positive definite, or CHOLMOD did not keep the seam unknowns last
        (the caller factors otherwise).
    """

    def __init__(self, L: sp.spmatrix, last: np.ndarray) -> None:
        from cvxopt import amd, cholmod

        L = sp.csc_matrix(L)
        _finite(L)
        if not L.has_sorted_indices:
            L = L.sorted_indices()  # a copy: the caller's matrix stays as it was
        N = L.shape[0]
        self.N, self.last = N, np.asarray(last, dtype=np.int64)
        slot = np.full(N, -1, dtype=np.int64)
        slot[self.last] = np.arange(len(self.last))
        groups, local = _components(L)
        self._parts: list[dict] = []
        taken: list[_Symbolic] = []
        seen: dict[tuple[int, int], list[tuple[sp.csc_matrix, dict]]] = {}  # by shape
        for g in groups:
            g = _as_slice(g)
            block = _column_block(L, g, local)
            sl = slot[g]
            seam = np.flatnonzero(sl >= 0)
            seam = seam[np.argsort(sl[seam], kind="stable")]  # in the order of ``last``
            key = (block.shape[0], block.nnz)
            twin = next(
                (
                    q
                    for other, q in seen.get(key, ())
                    if np.array_equal(q["seam"], seam) and _equal(other, block)
                ),
                None,
            )
            if twin is not None:
                twin["members"].append(g)
                twin["slots"].append(sl[twin["order"]])
                continue
            perm = None
            if len(seam):
                p0 = np.asarray(amd.order(_cvx(block))).ravel()
                is_seam = np.zeros(block.shape[0], dtype=bool)
                is_seam[seam] = True
                perm = np.concatenate([p0[~is_seam[p0]], seam])
            solve, getfactor = _factor_part(block, cholmod, taken, perm)
            part = {"members": [g], "solve": solve, "seam": seam, "T": None}
            order = seam
            if len(seam):
                k, ns = block.shape[0], len(seam)
                pos = solve(np.arange(k, dtype=float), 8)  # each unknown's place in the factor
                pos = np.rint(pos).astype(np.int64)
                order = np.argsort(pos[seam], kind="stable")
                ib = pos[seam][order]
                if not np.array_equal(ib, np.arange(k - ns, k)):
                    raise ArithmeticError("the seam unknowns are not last in the factor")
                order = seam[order]
                part["trailing"] = (getfactor, ib)
            part.update(order=order, slots=[sl[order]])  # each member's places in ``last``
            seen.setdefault(key, []).append((block, part))
            self._parts.append(part)

    @staticmethod
    def _T(part: dict) -> np.ndarray | None:
        """The block's trailing factor ``T`` (read out of CHOLMOD's factor once, when the
        seam step first needs it), None without seam unknowns."""
        if part["T"] is None and "trailing" in part:
            from cvxopt import matrix

            getfactor, ib = part.pop("trailing")
            Lf = getfactor()
            idx = matrix(ib.astype(int))
            part["T"] = np.tril(np.array(matrix(Lf[idx, idx])))
        return part["T"]

    def __call__(self, b: np.ndarray) -> np.ndarray:
        """``A^-1 b`` for ``b`` ``(N,)`` or ``(N, c)``."""
        rhs = np.asarray(b, dtype=float).reshape(len(b), -1)
        c = rhs.shape[1]
        out = np.empty_like(rhs)
        for part in self._parts:
            sol = part["solve"](np.concatenate([rhs[g] for g in part["members"]], axis=1))
            for j, g in enumerate(part["members"]):
                out[g] = sol[:, j * c : (j + 1) * c]
        return out.reshape(np.shape(b))

    def forward(self, b: np.ndarray) -> list[np.ndarray]:
        """The forward substitutions ``z = L^-1 P b`` of each block, ``b`` ``(N, c)``."""
        out = []
        for part in self._parts:
            rhs = np.concatenate([b[g] for g in part["members"]], axis=1)
            out.append(part["solve"](part["solve"](rhs, 7), 4))
        return out

    def seam_values(self, Z: list[np.ndarray], c: int) -> np.ndarray:
        """``(A^-1 b)`` at the seam unknowns, ``(s, c)`` in the order of ``last``, from
        :meth:`forward`'s ``Z`` (``c`` columns of ``b``)."""
        from scipy.linalg import solve_triangular

        out = np.zeros((len(self.last), c))
        for part, z in zip(self._parts, Z, strict=True):
            T = self._T(part)
            if T is None:
                continue
            ns = len(T)
            ys = solve_triangular(T, z[-ns:], lower=True, trans="T", check_finite=False)
            for j, slots in enumerate(part["slots"]):
                out[slots] = ys[:, j * c : (j + 1) * c]
        return out

    def finish(self, Z: list[np.ndarray], c: int, w: np.ndarray | None = None) -> np.ndarray:
        """``A^-1 (b - E w)`` from :meth:`forward`'s ``Z`` for ``w`` ``(s, c)`` on the seam
        unknowns (``E`` their columns of the identity; None: ``A^-1 b``), ``(N, c)``.
        ``Z`` is not changed."""
        from scipy.linalg import solve_triangular

        out = np.empty((self.N, c))
        for part, z in zip(self._parts, Z, strict=True):
            T = self._T(part) if w is not None else None
            if T is not None:
                ns = len(T)
                ws = np.concatenate([w[slots] for slots in part["slots"]], axis=1)
                z = z.copy()
                z[-ns:] -= solve_triangular(T, ws, lower=True, check_finite=False)
            sol = part["solve"](part["solve"](z, 5), 8)
            for j, g in enumerate(part["members"]):
                out[g] = sol[:, j * c : (j + 1) * c]
        return out

    def blocks(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """``A^-1`` on each block's seam unknowns: (positions in ``last``, ``(k, k)``
        dense), one per member of a block with seam unknowns (zero across blocks)."""
        from scipy.linalg import lapack

        out = []
        for part in self._parts:
            T = self._T(part)
            if T is None:
                continue
            G, info = lapack.dpotri(T, lower=1)
            if info != 0 or not np.all(np.isfinite(G)):
                raise ArithmeticError("the seam block of the inverse is not finite")
            G = np.tril(G) + np.tril(G, -1).T
            out += [(slots, G) for slots in part["slots"]]
        return out


def _components(L: sp.csc_matrix) -> tuple[list[np.ndarray], np.ndarray]:
    """The connected components of ``L``'s pattern (explicit zeros count), singletons
    together as one diagonal block, and each unknown's position in its component."""
    from scipy.sparse.csgraph import connected_components

    ones = np.ones(len(L.indices), dtype=np.int8)
    k, label = connected_components(sp.csc_matrix((ones, L.indices, L.indptr), L.shape), False)
    size = np.bincount(label, minlength=k)
    label = np.where(size[label] > 1, label, k)
    groups = _groups(label)
    local = np.empty(L.shape[0], dtype=np.int32)
    for g in groups:
        local[g] = np.arange(len(g), dtype=np.int32)
    return groups, local


def _equal(a: sp.csc_matrix, b: sp.csc_matrix) -> bool:
    """The same pattern and values (sorted CSC)."""
    return (
        np.array_equal(a.indptr, b.indptr)
        and np.array_equal(a.indices, b.indices)
        and np.array_equal(a.data, b.data)
    )


def _column_block(L: sp.csc_matrix, g: slice | np.ndarray, local: np.ndarray) -> sp.csc_matrix:
    """The columns ``g`` of ``L`` over their own rows (``local``: each row's position in
    its component): for a slice, cut from ``L``'s arrays (the same entries in the same
    order as indexing gives, without its copies; views: only of sorted columns, which
    the factorisation never sorts in place)."""
    if isinstance(g, slice) and L.has_sorted_indices:
        a, b = L.indptr[g.start], L.indptr[g.stop]
        k = g.stop - g.start
        ptr = L.indptr[g.start : g.stop + 1] - a
        return sp.csc_matrix((L.data[a:b], L.indices[a:b] - g.start, ptr), shape=(k, k))
    if isinstance(g, slice):
        g = np.arange(g.start, g.stop)
    C = L[:, g]
    return sp.csc_matrix((C.data, local[C.indices], C.indptr), shape=(len(g), len(g)))


def _as_slice(g: np.ndarray) -> slice | np.ndarray:
    """``g`` (increasing indices) as a slice when they are consecutive, else ``g``."""
    if len(g) and g[-1] - g[0] == len(g) - 1:
        return slice(int(g[0]), int(g[-1]) + 1)
    return g


def _cvx(L: sp.csc_matrix):
    """A CSC matrix (sorted indices) as a cvxopt ``spmatrix``."""
    from cvxopt import matrix, spmatrix

    n = L.shape[0]
    cols = np.repeat(np.arange(n), np.diff(L.indptr))
    return spmatrix(matrix(L.data), matrix(L.indices.astype(int)), matrix(cols), (n, n))


def _symbolic(
    L: sp.csc_matrix, cholmod, taken: list[_Symbolic], perm: np.ndarray | None = None
) -> _Symbolic:
    """The analysis for ``L``'s pattern (in the ordering ``perm``, default CHOLMOD's
    choice): the active cache's, else a new one (cached); never one of ``taken`` (the
    other blocks of one matrix: two panels of one mesh have one pattern, but each needs
    its own factor)."""
    shared = _SHARED.get()
    for sym in shared or ():
        if any(sym is t for t in taken):
            continue
        if (
            np.array_equal(sym.indptr, L.indptr)
            and np.array_equal(sym.indices, L.indices)
            and (sym.perm is None) == (perm is None)
            and (perm is None or np.array_equal(sym.perm, perm))
        ):
            return sym
    S = _cvx(L)
    sym = _Symbolic(L.indptr, L.indices, S, _analysis(S, cholmod, perm), perm=perm)
    if shared is not None:
        shared.append(sym)
    return sym


def _analysis(S, cholmod, perm: np.ndarray | None):
    """CHOLMOD's symbolic analysis of ``S`` (supernodal): the least fill of three
    orderings, or ``perm`` as it is (no postordering, so its last unknowns stay last)."""
    from cvxopt import matrix

    with _OPTIONS:
        saved = dict(cholmod.options)
        cholmod.options.update(supernodal=2, nmethods=3 if perm is None else 1)
        if perm is not None:
            cholmod.options["postorder"] = False
        try:
            if perm is None:
                return cholmod.symbolic(S, uplo="L")
            return cholmod.symbolic(S, p=matrix(perm.astype(int)), uplo="L")
        finally:
            cholmod.options.clear()
            cholmod.options.update(saved)


def _factor_part(
    L: sp.csc_matrix, cholmod, taken: list[_Symbolic] | None = None, perm=None
) -> tuple[Callable[..., np.ndarray], Callable[[], object]]:
    """:func:`_cholmod`'s solve function, ``solve(b, sys=0)`` (CHOLMOD's ``sys``: 0 the
    whole solve, 4 and 5 ``L`` and ``L^T``, 7 and 8 the permutation and its inverse), in
    the ordering ``perm`` (default CHOLMOD's), and ``getfactor()``: the
    factor ``L`` as a cvxopt sparse matrix (with a ``perm``, the matrix is kept for it:
    CHOLMOD's factor turns symbolic when read out, and is factored again)."""
    from cvxopt import matrix

    L.sort_indices()
    data = L.data
    taken = [] if taken is None else taken
    sym = _symbolic(L, cholmod, taken, perm)
    taken.append(sym)
    token = object()

    def refactor() -> None:
        if sym.owner is not token:  # new, or another factorisation of this pattern came since
            if sym.owner is not None:
                sym.S.V = matrix(data)
            cholmod.numeric(sym.S, sym.F)
            sym.owner = token

    refactor()
    shared = _SHARED.get()
    if perm is None and (not shared or sym not in shared):
        # nobody else refactors it: the factor alone serves the solves (the matrix's
        # copies go: 16 MB at 300k triangles)
        sym.S, data = None, None

    def solve(b: np.ndarray, sys: int = 0) -> np.ndarray:
        refactor()
        B = matrix(np.asarray(b, dtype=float).reshape(len(b), -1, order="F"))
        cholmod.solve(sym.F, B, sys=sys)
        return np.asarray(B).reshape(np.shape(b))

    def getfactor():
        refactor()  # this matrix's values in the factor and in sym.S
        Lf = cholmod.getfactor(sym.F)
        # reading it out leaves CHOLMOD's factor unusable: analysed and factored again
        # (in the same ordering: the same factor)
        sym.F = _analysis(sym.S, cholmod, perm)
        cholmod.numeric(sym.S, sym.F)
        return Lf

    return solve, getfactor


def _superlu(A: sp.csc_matrix, *, lower: bool = False):
    """SuperLU's solve function for ``A`` (symmetric mode; ``lower``: ``A`` is the lower
    triangle of the symmetric matrix)."""
    from scipy.sparse.linalg import splu

    from ptailor.errors import PtailorError

    if lower:
        A = sp.csc_matrix(A + sp.tril(A, -1).T)

    try:
        lu = splu(
            A,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise PtailorError(
            f"flatten: the stitching matrix cannot be factored ({exc}): degenerate target "
            "triangles or extreme flatten weights"
        ) from None
    return lu.solve


@dataclass(frozen=True)
class SeamBlock:
    """The seam unknowns' block of ``A^-1``, dense per block of ``A`` (zero across).

    Attributes
    ----------
    U : (2q,) int array
        The seam unknowns (indices into ``[x; y]``).
    blocks : list of ((k,) int array, (k, k) float array)
        Positions in ``U`` of one block's unknowns, and ``A^-1`` restricted to them.
    """

    U: np.ndarray
    blocks: list[tuple[np.ndarray, np.ndarray]]

    @cached_property
    def _by_block(self) -> tuple[np.ndarray, np.ndarray]:
        """Positions in ``U`` block after block, and each block's range in that order."""
        order = np.concatenate([idx for idx, _ in self.blocks]) if self.blocks else self.U[:0]
        bounds = np.cumsum([0] + [len(idx) for idx, _ in self.blocks])
        return order, bounds

    @cached_property
    def _local(self) -> np.ndarray:
        """Position in ``U`` of each unknown (-1 off the seams), ``(max(U) + 1,)`` int."""
        local = np.full(int(self.U.max(initial=-1)) + 1, -1, dtype=np.int64)
        local[self.U] = np.arange(len(self.U))
        return local

    def restrict(self, C: sp.spmatrix) -> sp.csr_matrix:
        """Rows over all unknowns ``[x; y]`` that touch only seam unknowns, as rows over
        ``U`` (``C[:, U]``, by renumbering the columns: no column search)."""
        C = sp.csr_matrix(C)
        cols = self._local[C.indices]
        return sp.csr_matrix((C.data, cols, C.indptr), shape=(C.shape[0], len(self.U)))

    def products(self, C: sp.spmatrix) -> tuple[int, list]:
        """Per block, the rows of ``C (r, 2q)`` over ``U`` that touch the block, cut to its
        unknowns, and their product with the block's ``G``: the pieces of :meth:`schur`,
        kept to pair the same rows with others without multiplying them again.

        Returns
        -------
        (r, list of ((r_b,) int array, (r_b, k_b) sparse, (r_b, k_b) float array))
            The rows of ``C``, and per block with rows the rows' positions, the rows and
            their product (a row touches few blocks: the products are ``r_b x k_b``, not
            ``r x k_b``, 60 MB apiece at 300,000 triangles)."""
        order, bounds = self._by_block
        Cb_all = sp.csc_matrix(C)[:, order]  # block after block: each block is a slice
        out = []
        for k, (_, G) in enumerate(self.blocks):
            Cb = Cb_all[:, bounds[k] : bounds[k + 1]]
            if not Cb.nnz:
                continue
            rows = np.unique(Cb.indices)  # CSC: its row indices, renumbered onto ``rows``
            Cr = sp.csc_matrix(
                (Cb.data, np.searchsorted(rows, Cb.indices), Cb.indptr),
                shape=(len(rows), Cb.shape[1]),
            )
            out.append((k, rows, Cr, Cr @ G))
        return C.shape[0], out

    def schur(self, C, D=None, *, out: np.ndarray | None = None) -> np.ndarray:
        """``C G D^T`` (default ``D = C``) for rows ``C (r, 2q)`` and ``D (t, 2q)`` over
        ``U`` (sparse, or their :meth:`products`), ``(r, t)`` dense; added to ``out`` (a
        zero view of a larger matrix, say) where given."""
        Cp = C if isinstance(C, tuple) else self.products(C)
        Dp = Cp if D is None else D if isinstance(D, tuple) else self.products(D)
        M = np.zeros((Cp[0], Dp[0])) if out is None else out
        d_by_block = {k: (rows, DG) for k, rows, _, DG in Dp[1]}
        for k, rows, Cr, _ in Cp[1]:
            if k in d_by_block:
                drows, DG = d_by_block[k]
                M[np.ix_(rows, drows)] += Cr @ DG.T  # G is symmetric: C G D^T = C (D G)^T
        return M


def seam_block(
    solve_many,
    ease: SeamEase,
    vertex_panel: np.ndarray,
    n: int,
    *,
    coupled: bool,
    A: sp.spmatrix | None = None,
) -> SeamBlock:
    """The seam vertices' block of ``A^-1``, computed once per factorisation.

    With ``A`` (and CHOLMOD): from a Cholesky factorisation that eliminates the seam
    unknowns last, where the trailing block of the factor is the Cholesky factor of the
    Schur complement ``S`` onto them and ``A^-1`` restricted to them is ``S^-1`` (one
    factorisation and a dense inverse per block, instead of a back-substitution per seam
    unknown). Otherwise by back-substitution: ``A`` is block diagonal by panel (and by
    coordinate when x and y decouple), so one right-hand side serves one seam unknown of
    every block at once.

    Parameters
    ----------
    solve_many : callable
        ``(2n, c) -> (2n, c)``: ``A^-1`` applied to columns over unknowns ``[x; y]``.
    ease : SeamEase
    vertex_panel : (n,) int array
        Panel of each pattern vertex.
    n : int
    coupled : bool
        Whether ``A`` couples x and y (the as-similar-as-possible term).
    A : sparse matrix, optional
        The factored matrix (``2n x 2n`` when coupled, else ``n x n``).

    Returns
    -------
    SeamBlock
    """
    verts = ease.vertices()
    U = np.concatenate([verts, verts + n])
    q = len(verts)
    pan = vertex_panel[verts].astype(np.int64)
    if coupled:
        groups = _groups(np.concatenate([pan, pan]))
        unknowns = U
    else:  # one n x n block per panel serves x and y
        groups = _groups(pan)
        unknowns = verts
    inv = _schur_inverses(A, unknowns, groups) if A is not None else None
    if inv is None:
        inv = _solved_inverses(solve_many, U if coupled else U[:q], groups, 2 * n)
    blocks = list(zip(groups, inv, strict=True))
    if not coupled:
        blocks += [(g + q, G) for g, G in blocks]
    return SeamBlock(U=U, blocks=blocks)


def _groups(label: np.ndarray) -> list[np.ndarray]:
    """Positions of each label's members, labels in increasing order."""
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    return np.split(order, cuts)


def _solved_inverses(solve_many, U: np.ndarray, groups, size: int) -> list[np.ndarray]:
    """Per group, ``A^-1`` on its unknowns by back-substitution: right-hand side ``j``
    holds the ``j``-th unknown of every group (the groups are separate blocks of ``A``)."""
    slot = np.empty(len(U), dtype=np.int64)
    for g in groups:
        slot[g] = np.arange(len(g))
    out = [np.empty((len(g), len(g))) for g in groups]
    n_slots = max(len(g) for g in groups)
    for s0 in range(0, n_slots, tol.SEAM_BLOCK_CHUNK):  # chunks of right-hand sides
        s1 = min(s0 + tol.SEAM_BLOCK_CHUNK, n_slots)
        pick = (slot >= s0) & (slot < s1)
        rhs = np.zeros((size, s1 - s0))
        rhs[U[pick], slot[pick] - s0] = 1.0
        sol = solve_many(rhs)
        for g, G in zip(groups, out, strict=True):
            e = min(s1, len(g))
            if e > s0:
                G[:, s0:e] = sol[U[g], : e - s0]
    return [0.5 * (G + G.T) for G in out]


def _schur_inverses(A: sp.spmatrix, unknowns: np.ndarray, groups) -> list[np.ndarray] | None:
    """Per group, ``A^-1`` on its unknowns from the Schur complements of a CHOLMOD
    factorisation that orders them last; None without cvxopt or if it fails."""
    try:
        from cvxopt import amd, cholmod, matrix
    except ImportError:  # pragma: no cover - cvxopt is a dependency
        return None
    from scipy.linalg import lapack

    L = sp.tril(sp.csc_matrix(A), format="csc")
    L.sort_indices()
    N = L.shape[0]
    S = _cvx(L)
    p0 = np.asarray(amd.order(S)).ravel()
    last = np.zeros(N, dtype=bool)
    last[unknowns] = True
    p = np.concatenate([p0[~last[p0]], unknowns[np.concatenate(groups)]])
    with _OPTIONS:
        saved = dict(cholmod.options)
        cholmod.options.update(supernodal=2, nmethods=1)  # this order, not AMD's
        try:
            F = cholmod.symbolic(S, p=matrix(p.astype(int)), uplo="L")
            cholmod.numeric(S, F)
        except (ArithmeticError, ValueError):
            return None
        finally:
            cholmod.options.clear()
            cholmod.options.update(saved)
    pos = matrix(np.arange(N, dtype=float))
    cholmod.solve(F, pos, sys=8)  # where each unknown sits in the (postordered) factor
    pos = np.rint(np.asarray(pos).ravel()).astype(np.int64)
    Lf = cholmod.getfactor(F)
    out = []
    for g in groups:
        ib = pos[unknowns[g]]
        o = np.argsort(ib)
        idx = matrix(ib[o].astype(int))
        T = np.array(matrix(Lf[idx, idx]))  # Cholesky factor of the Schur complement
        Ginv, info = lapack.dpotri(T, lower=1)
        if info != 0 or not np.all(np.isfinite(Ginv)):
            return None
        Ginv = np.tril(Ginv) + np.tril(Ginv, -1).T
        back = np.empty_like(o)
        back[o] = np.arange(len(o))
        out.append(Ginv[np.ix_(back, back)])
    return out


def spd_factor(M: np.ndarray) -> Callable[[np.ndarray], np.ndarray | None] | None:
    """The solution operator of a small symmetric positive (semi-)definite ``M``, factored
    once: Cholesky; where ``M`` is singular (dependent seam rows, as on a degenerate drape),
    Cholesky of ``M + eps I`` (``eps`` 1e-12, then 1e-9 of the largest diagonal entry: the
    least-squares solution to that precision, at a Cholesky's cost); least squares only
    where neither factors. None when ``M`` is not finite.

    A least-squares solve per right-hand side (an SVD of the whole seam system) once made
    every step of a degenerate run cost 20 s."""
    import scipy.linalg as sla

    if not np.all(np.isfinite(M)):
        return None
    d = float(np.abs(np.diag(M)).max(initial=0.0)) if M.size else 0.0
    for eps in (0.0, 1e-12, 1e-9):
        try:
            A = M if eps == 0.0 else M + (eps * max(d, 1e-300)) * np.eye(len(M))
            cho = sla.cho_factor(A)
        except (sla.LinAlgError, ValueError):
            continue
        return lambda r: _finite_or_none(sla.cho_solve(cho, r)) if np.all(np.isfinite(r)) else None

    def lstsq(r: np.ndarray) -> np.ndarray | None:
        if not np.all(np.isfinite(r)):
            return None
        try:
            return _finite_or_none(np.linalg.lstsq(M, r, rcond=None)[0])
        except (np.linalg.LinAlgError, ValueError):
            return None

    return lstsq


def solve_spd(M: np.ndarray, r: np.ndarray) -> np.ndarray | None:
    """Solve a small symmetric positive (semi-)definite system (:func:`spd_factor`).

    None when there is no finite solution (the caller skips the constraints).
    """
    if not np.all(np.isfinite(r)):
        return None
    solve = spd_factor(M)
    return None if solve is None else solve(r)


def solve_bordered(M: np.ndarray, B: np.ndarray | None, r: np.ndarray) -> np.ndarray | None:
    """``u`` of ``[[M, B], [B^T, 0]] [u; w] = [r; 0]`` for a symmetric positive
    (semi-)definite ``M``: :func:`bordered_solver` applied once. None when there is no
    finite solution.

    Parameters
    ----------
    M : (k, k) float array
    B : (k, t) float array or None
    r : (k,) float array
    """
    solve = bordered_solver(M, B)
    return None if solve is None else solve(r)


def bordered_solver(
    M: np.ndarray, B: np.ndarray | None
) -> Callable[[np.ndarray], np.ndarray | None] | None:
    """The solution operator ``r -> u`` of ``[[M, B], [B^T, 0]] [u; w] = [r; 0]`` for a
    symmetric positive (semi-)definite ``M`` (the seam step's system with free factors
    ``w``, one per column of ``B``), factored once for many right-hand sides.

    By the range space on ``M' = M + rho B B^T`` (the same solution, as ``B^T u = 0``;
    positive definite where ``M`` is singular only along directions ``B`` sees, as when a
    curve's total row is the sum of its pairs' rows): ``(B^T M'^-1 B) w = B^T M'^-1 r``,
    ``u = M'^-1 (r - B w)``. Without ``B``, :func:`solve_spd`'s Cholesky (least squares
    where singular).

    Parameters
    ----------
    M : (k, k) float array
    B : (k, t) float array or None
        Columns with disjoint supports (each row in at most one column: a seam curve's
        pairs), so ``B B^T`` is one rank-1 block per column.

    Returns
    -------
    callable or None
        ``solve(r)``, ``r`` a ``(k,)`` float array, giving ``u`` or None where it is not
        finite; None when ``M`` or ``B`` is not finite or the system has no solution.
    """

    if not np.all(np.isfinite(M)):
        return None
    if B is None or B.shape[1] == 0:
        return spd_factor(M)
    if not np.all(np.isfinite(B)):
        return None
    Mp = M.copy()
    rho = float(np.abs(np.diag(M)).max(initial=0.0)) / max(float((B * B).sum(1).max()), 1e-300)
    for j in range(B.shape[1]):  # a loop over the seam curves
        idx = np.flatnonzero(B[:, j])
        b = B[idx, j]
        Mp[np.ix_(idx, idx)] += rho * np.outer(b, b)
    inner = spd_factor(Mp)
    if inner is None:
        return None
    MB = inner(B)
    if MB is None:
        return None
    S = B.T @ MB

    def solve(r: np.ndarray) -> np.ndarray | None:
        if not np.all(np.isfinite(r)):
            return None
        u0 = inner(r)
        if u0 is None:
            return None
        w = solve_spd(S, B.T @ u0)
        return None if w is None else _finite_or_none(u0 - MB @ w)

    return solve


def _finite_or_none(u: np.ndarray) -> np.ndarray | None:
    return u if np.all(np.isfinite(u)) else None
