"""The safe expression parser: spec text -> sympy, from a whitelist.

A spec is untrusted input, so its text is never evaluated (`eval`, `exec`,
`sympify` and `parse_expr` are all off limits). Python's `ast` only parses the
text; `_Builder` then walks the tree and accepts exactly the node types of the
contract's expression language, building sympy objects directly:

    numbers, names, + - * / ** ^, parentheses, unary +/-,
    calls of the functions in FUNCTIONS (positional arguments only),
    diff(expr, t) = total time derivative.

Anything else (attributes, subscripts, strings, lambdas, comprehensions,
keyword arguments, comparisons ...) is a `SpecError` naming the construct.
Sizes are bounded so that no input can make sympy hang: text length, tree
size and depth, and the magnitude of numeric powers.
"""
from __future__ import annotations

import ast
import difflib
import math
import re
import sys
from collections.abc import Callable, Mapping
from contextlib import contextmanager
from dataclasses import dataclass

import sympy as sp

from lagcli.model.angle_calls import TRIG, trig_call
from lagcli.model.constants import ConstantError, constant_value
from lagcli.model.products import product
from lagcli.model.sums import negative, total
from lagcli.errors import Loc, Problem, SpecError
from lagcli.spec.slips import EQUATION_HINT, expression_syntax_hint

MAX_TEXT = 20_000        # characters in one expression
MAX_NODES = 5_000        # syntax-tree nodes in one expression
MAX_DEPTH = 60           # nesting depth
MAX_EXPONENT = 1_000     # |n| in x**n with a numeric n
MAX_LITERAL_DIGITS = 40  # digits in one numeric literal
MAX_RESULT_NODES = 20_000  # tree size of one expression after definitions are substituted
MAX_RESULT_DEPTH = 100     # its nesting depth (sympy recurses, and slows, with depth)
MAX_EXACT_DIGITS = 20      # digits of a number kept exact under a fractional power
MAX_EXACT_ROOT = 12        # ... and the highest root kept exact (x**(1/3) yes, 12**-0.007 no)
MAX_EXACT_NUMBER_DIGITS = 1_000  # digits of the numerator or denominator of any exact number built
MAX_LITERAL_EXPONENT = 400       # |e| in a literal 1e-400: beyond it the double is 0 or inf anyway


@dataclass(frozen=True)
class Limits:
    """How large a text `parse` takes: a spec's expressions are untrusted and small; the
    expressions lagcli printed itself (JSON reports, parsed back by `parse_output`) can
    be megabytes for a bicycle-sized system."""

    text: int = MAX_TEXT
    nodes: int = MAX_NODES
    depth: int = MAX_DEPTH
    result_nodes: int = MAX_RESULT_NODES


# A sum a + b + ... counts as one level of nesting however many terms it has (Python's tree
# nests it one level per term; `_check_size` and `_Builder._sum` walk it in a loop), so the
# depth bound is about real nesting (parentheses, calls, products, powers), not length: the
# 100-link chain's positions are flat sums of 100 terms. Python's parser still recurses once
# per term while it builds that tree: `parse` gives it room for as many terms as the text
# bound allows (a term is at least a character and its sign).


SPEC_LIMITS = Limits()
OUTPUT_LIMITS = Limits(text=50_000_000, nodes=10_000_000, depth=200, result_nodes=10_000_000)
OUTPUT_SUM_TERMS = 20_000   # room for this many terms in one sum of an output's text


_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+$")   # the lines ast numbers (no form feeds)


@contextmanager
def _recursion_limit(limit: int):
    """Python's parser builds a sum of n terms as a tree n deep, recursively."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, limit))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)


def _atan2(y, x):
    return sp.atan2(y, x)


FUNCTIONS: dict[str, tuple[Callable, int, int]] = {
    # name: (sympy constructor, min args, max args)
    "sin": (sp.sin, 1, 1), "cos": (sp.cos, 1, 1), "tan": (sp.tan, 1, 1),
    "asin": (sp.asin, 1, 1), "acos": (sp.acos, 1, 1), "atan": (sp.atan, 1, 1),
    "atan2": (_atan2, 2, 2),
    "sinh": (sp.sinh, 1, 1), "cosh": (sp.cosh, 1, 1), "tanh": (sp.tanh, 1, 1),
    "exp": (sp.exp, 1, 1), "log": (sp.log, 1, 1), "sqrt": (sp.sqrt, 1, 1),
    "abs": (sp.Abs, 1, 1), "sign": (sp.sign, 1, 1),
    "min": (sp.Min, 2, 16), "max": (sp.Max, 2, 16),
    "diff": (None, 2, 2),  # handled specially: total time derivative
}

RESERVED_NAMES = frozenset({"t", "pi", *FUNCTIONS})

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: product(a, b) if isinstance(a, sp.Expr) and isinstance(b, sp.Expr) else a * b,
    ast.Div: lambda a, b: a / b,
}

_FORBIDDEN_NAMES = {
    ast.Attribute: "attribute access", ast.Subscript: "subscripts",
    ast.Lambda: "lambdas", ast.ListComp: "comprehensions", ast.SetComp: "comprehensions",
    ast.DictComp: "comprehensions", ast.GeneratorExp: "comprehensions",
    ast.Compare: "comparisons", ast.BoolOp: "boolean operators", ast.IfExp: "conditional expressions",
    ast.List: "lists", ast.Tuple: "tuples", ast.Dict: "dictionaries", ast.Set: "sets",
    ast.JoinedStr: "strings", ast.NamedExpr: "assignment expressions", ast.Starred: "starred arguments",
    ast.Await: "await", ast.Yield: "yield", ast.YieldFrom: "yield", ast.Slice: "slices",
}


class Scope:
    """The names an expression may use and what they stand for.

    `names` maps a name to its sympy value (a symbol, or an already-built
    expression for known functions and definitions). `time_derivative` is the
    total time derivative operator used by `diff(expr, t)`. `builder` is the tree
    walker (`_Builder` here; lagcli/model/vectors.py's adds vectors, frames and kinematics).
    `elsewhere` maps names of the spec that cannot be used here to (message, hint), said
    instead of "unknown name" (a parameter in another parameter's value).
    """

    def __init__(self, names: Mapping[str, sp.Expr], t: sp.Symbol,
                 time_derivative: Callable[[sp.Expr], sp.Expr] | None = None, builder: type | None = None,
                 elsewhere: Mapping[str, tuple[str, str]] | None = None):
        self.names = dict(names)
        self.t = t
        self.time_derivative = time_derivative
        self.builder = builder or _Builder
        self.elsewhere = elsewhere if elsewhere is not None else {}     # read only: looked up
        self.built: dict = {}    # (builder, a sum's term as written) -> (names, their values, the term)
        self.memo: dict = {}     # the builders' memos of expressions (`_Builder`)

    def with_name(self, name: str, value: sp.Expr) -> "Scope":
        return Scope({**self.names, name: value}, self.t, self.time_derivative, self.builder, self.elsewhere)


def parse(text: str, scope: Scope, loc: Loc, vector: bool = False, limits: Limits = SPEC_LIMITS) -> sp.Expr:
    """Parse `text` into a sympy expression using only names in `scope` (a vector
    expression, lagcli/model/vectors.py's `Vector`, when `vector` is true), refusing a text
    beyond `limits`."""
    if len(text) > limits.text:
        _fail(loc, f"expression is too large ({len(text)} characters, at most {limits.text})")
    # `^` is a power, as in most maths notations; Python's ^ would bind looser than `*`.
    source = text.replace("^", "**").strip()
    if not source:
        _fail(loc, "empty expression")
    try:
        with _recursion_limit(min(OUTPUT_SUM_TERMS, limits.text // 2 + 100)):
            tree = ast.parse(source, mode="eval")
    except SyntaxError as exc:
        _fail(loc, f"invalid expression {text!r}: {exc.msg}" + (f" at column {exc.offset}" if exc.offset else ""),
              expression_syntax_hint(text, toml=loc.file.endswith(".toml")))
    except (RecursionError, MemoryError, ValueError):
        _fail(loc, f"expression is too deeply nested or too large: {_short(text)!r}")
    _check_size(tree, text, loc, limits)
    builder = scope.builder(scope, loc, text)
    value = builder.finish(builder.build(tree.body), vector)
    sizes, unreal = scope.memo.setdefault("sizes", {}), scope.memo.setdefault("unreal", {})
    for part in getattr(value, "components", (value,)):
        if _tree_size(part, sizes) > limits.result_nodes + 1:
            _fail(loc, f"expression is too large once names are substituted (more than {limits.result_nodes} "
                       "terms); split it or simplify the definitions it uses")
        if _unreal(part, unreal):
            _fail(loc, f"{_short(text)!r} is complex or infinite; expressions must be real")
    return value


def parse_constant(text: str, loc: Loc, extra: Mapping[str, sp.Expr] | None = None,
                   elsewhere: Mapping[str, tuple[str, str]] | None = None) -> float:
    """Parse a constant expression (numbers, pi, and `extra` names) to a float; `elsewhere`
    as for `Scope`."""
    names = {"pi": sp.pi, **(extra or {})}
    value = parse(text, Scope(names, sp.Symbol("t"), elsewhere=elsewhere), loc)
    if value.free_symbols:
        names_used = ", ".join(sorted(str(s) for s in value.free_symbols))
        _fail(loc, f"{_short(text)!r} must be a constant, but uses {names_used}")
    try:
        return constant_value(value)
    except ConstantError as exc:
        _fail(loc, f"{_short(text)!r} {exc}", "a value must be a finite real number")


def _tree_size(expr: sp.Expr, sizes: dict) -> int:
    """The number of nodes `sympy.preorder_traversal(expr)` visits (a shared subexpression
    at each occurrence), each subexpression's remembered in `sizes`: a chain's positions
    share their terms, which counting the traversal walked again in every position.
    (Counting the traversal up to a bound b said "too large" from b + 2 nodes on.)"""
    found = sizes.get(expr)
    if found is None:
        found = sizes[expr] = 1 + sum(_tree_size(arg, sizes) for arg in expr.args)
    return found


_UNREAL = frozenset((sp.I, sp.zoo, sp.nan, sp.oo))


def _unreal(expr: sp.Expr, memo: dict) -> bool:
    """`expr.has(sp.I, sp.zoo, sp.nan, sp.oo)`, each subexpression's answer remembered in
    `memo` (`has` walks the whole tree five times: once for all four, then once for each)."""
    found = memo.get(expr)
    if found is None:
        found = memo[expr] = expr in _UNREAL or any(_unreal(arg, memo) for arg in expr.args)
    return found


def _check_size(tree: ast.AST, text: str, loc: Loc, limits: Limits) -> None:
    """Refuse a tree of more than limits.nodes nodes or nested more than limits.depth deep.
    Measured first by `_within_limits`; a tree beyond them is walked again by
    `_refuse_size`, which says which bound it meets first, as it always did."""
    if not _within_limits(tree, limits):
        _refuse_size(tree, text, loc, limits)


def _within_limits(tree: ast.AST, limits: Limits) -> bool:
    """At most limits.nodes nodes and limits.depth levels, counted as `_refuse_size`
    counts them. A name (with its context) or a number is counted where it is met, not
    pushed and popped, and a binary operation's operator likewise: the nodes of a sum of
    products, whose field-by-field walk was most of the time; any other node is taken
    apart by its fields, as `_refuse_size` does."""
    count, deepest, stack = 0, 0, [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        below = depth + 1
        if type(node) is ast.BinOp:     # left, op (no fields), right
            count += 2
            left = node.left
            continued = isinstance(node.op, _SUM_OPERATORS) and _is_sum(left)    # a sum continues its sum
            children = ((left, depth if continued else below), (node.right, below))
        else:
            count += 1
            children = []
            for name in node._fields:
                child = getattr(node, name, None)
                if isinstance(child, ast.AST):
                    children.append((child, below))
                elif isinstance(child, list):
                    children += [(item, below) for item in child if isinstance(item, ast.AST)]
        reach = below if children else depth       # a child (a binary operation's operator at least) is one below
        if reach > deepest:
            deepest = reach
        for child, at in children:
            kind = type(child)
            if kind is ast.Name:        # id, ctx (no fields)
                count += 2
                if at + 1 > deepest:
                    deepest = at + 1
            elif kind is ast.Constant:  # value, kind: no nodes
                count += 1
                if at > deepest:
                    deepest = at
            else:
                stack.append((child, at))
        if count > limits.nodes or deepest > limits.depth:
            return False
    return True


def _refuse_size(tree: ast.AST, text: str, loc: Loc, limits: Limits) -> None:
    """Refuse a tree of more than limits.nodes nodes or nested more than limits.depth deep,
    walking it depth first: the first bound met, in that order, is the one said.
    (`ast.iter_child_nodes` inlined: a generator per node was most of the time of this
    walk over a chain's positions.)"""
    count = 0
    stack = [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > limits.nodes:
            _fail(loc, f"expression is too large (more than {limits.nodes} terms)")
        if depth > limits.depth:
            _fail(loc, f"expression is nested too deeply (more than {limits.depth} levels): {_short(text)!r}")
        summing = isinstance(node, ast.BinOp) and isinstance(node.op, _SUM_OPERATORS)     # `_is_sum`
        for name in node._fields:      # the children in `ast.iter_child_nodes`'s order
            child = getattr(node, name, None)
            if isinstance(child, ast.AST):
                # the rest of a sum continues it: a + b + c is ((a + b) + c) in Python's tree
                stack.append((child, depth if summing and child is node.left and _is_sum(child) else depth + 1))
            elif isinstance(child, list):
                stack.extend((item, depth + 1) for item in child if isinstance(item, ast.AST))


_SUM_OPERATORS = (ast.Add, ast.Sub)


def _is_sum(node: ast.AST) -> bool:
    return isinstance(node, ast.BinOp) and isinstance(node.op, _SUM_OPERATORS)


class _Builder:
    """Walks a parsed tree, accepting only whitelisted nodes, and builds sympy objects."""

    def __init__(self, scope: Scope, loc: Loc, text: str):
        self.scope, self.loc, self.text = scope, loc, text
        self.source = text.replace("^", "**").strip()  # what `ast` parsed: node positions refer to it
        # what is known of the values built (pure functions of an expression, so kept in the
        # scope: a chain's positions share their terms, each walked once, not once a position)
        self.values: dict[sp.Expr, float] = scope.memo.setdefault("values", {})      # constant -> its value
        self.constant: dict[sp.Expr, bool] = scope.memo.setdefault("constant", {})   # expression -> no free symbols
        self.depths: dict[sp.Expr, int] = scope.memo.setdefault("depths", {})        # expression -> nesting depth

    def fail(self, message: str, hint: str = "") -> None:
        raise SpecError(Problem(self.loc, f"in {_short(self.text)!r}: {message}", hint))

    def segment(self, node: ast.AST) -> str | None:
        """The source text of `node`, as `ast.get_source_segment` gives it, from lines split
        once (get_source_segment splits the whole text at every call: quadratic in a
        report's long expressions)."""
        if not hasattr(self, "_lines"):
            self._lines = [line.encode() for line in _LINES.findall(self.source)]
        if getattr(node, "end_lineno", None) is None:
            return None
        first, last = node.lineno - 1, node.end_lineno - 1
        if first == last:
            return self._lines[first][node.col_offset:node.end_col_offset].decode()
        parts = [self._lines[first][node.col_offset:], *self._lines[first + 1:last],
                 self._lines[last][:node.end_col_offset]]
        return b"".join(parts).decode()

    def scalar(self, node: ast.AST) -> sp.Expr:
        """An operand that must be a scalar (every operand here; vectors.py checks it)."""
        return self.build(node)

    def finish(self, value: sp.Expr, vector: bool) -> sp.Expr:
        """The value of the whole expression, `vector` when a vector is expected."""
        if vector:
            self.fail("a vector is expected here")
        return value

    def build(self, node: ast.AST) -> sp.Expr:
        handler = getattr(self, "_" + type(node).__name__, None)
        if handler is None:
            what = _FORBIDDEN_NAMES.get(type(node), f"'{type(node).__name__}' syntax")
            self.fail(f"{what} are not allowed in expressions" if what.endswith("s")
                      else f"{what} is not allowed in expressions",
                      EQUATION_HINT if isinstance(node, ast.Compare) else
                      "expressions use numbers, names, + - * / ** ^, parentheses and functions "
                      + ", ".join(sorted(FUNCTIONS)))
        return self.guarded(handler(node), node)

    def guarded(self, value: sp.Expr, node: ast.AST) -> sp.Expr:
        """`value`, once each constant in its top node is known to be a finite real double.

        Checking every node as it is built means sympy never receives an argument
        that is complex, infinite or astronomically large: `Min(x, acos(2))` would
        raise inside sympy, `tan(cosh(10**6))` would grind through argument reduction.
        sympy merges numbers as it builds (x*1e300*1e300 -> 1e600*x), hence the
        check of the top node's constant arguments as well. Definitions nest, so the
        depth of the result is bounded here too, not only that of the text."""
        if self.depth(value) > MAX_RESULT_DEPTH:
            self.too_deep()
        for part in (value,) if self.is_constant(value) else value.args:
            if part.is_Rational and exact_digits(part) > MAX_EXACT_NUMBER_DIGITS:
                self.too_many_digits(exact_digits(part))
            if self.is_constant(part):
                try:
                    constant_value(part, self.values)
                except ConstantError as exc:
                    written = ast.get_source_segment(self.source, node) if part is value else None
                    self.fail(f"the constant {_short(written) if written else _number_text(part)} {exc}",
                              "constants must be finite real numbers within the double range")
        return value

    def depth(self, value: sp.Expr) -> int:
        found = self.depths.get(value)
        if found is None:
            found = 1 + max((self.depth(arg) for arg in value.args), default=0)
            self.depths[value] = found
        return found

    def too_deep(self) -> None:
        self.fail(f"expression is nested too deeply once names are substituted (more than "
                  f"{MAX_RESULT_DEPTH} levels)", "split the chain of definitions, or simplify it")

    def too_many_digits(self, digits: int) -> None:
        self.fail(f"an exact number here has about {digits} digits, more than the {MAX_EXACT_NUMBER_DIGITS} "
                  "that exact arithmetic is allowed", "write the numbers as floating-point values with fewer "
                  "digits, or simplify the arithmetic on them")

    def is_zero(self, value: sp.Expr) -> bool:
        """Exactly zero, or a constant whose double value is 0 (a 0.0 parameter value)."""
        return value.is_zero is True or (self.is_constant(value) and constant_value(value, self.values) == 0)

    def is_constant(self, value: sp.Expr) -> bool:
        found = self.constant.get(value)
        if found is None:
            found = not value.is_Symbol and all(self.is_constant(arg) for arg in value.args)
            self.constant[value] = found
        return found

    def _Constant(self, node: ast.Constant) -> sp.Expr:
        value = node.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            kind = "strings" if isinstance(value, (str, bytes)) else f"{type(value).__name__} literals"
            self.fail(f"{kind} are not allowed in expressions")
        literal = self.segment(node) or repr(value)
        if sum(c.isdigit() for c in literal) > MAX_LITERAL_DIGITS:
            self.fail(f"numeric literal {literal[:20]}... is too large")
        if isinstance(value, int):
            return sp.Integer(value)
        if not math.isfinite(value):
            self.fail(f"numeric literal {literal} is too large")
        if _literal_exponent(literal) > MAX_LITERAL_EXPONENT:  # 1e-1000000000: no billion-digit rational
            if value != 0 or not any(c in "123456789" for c in literal.lower().partition("e")[0]):
                return sp.Float(value)
            self.fail(f"the constant {literal} is too small (below 1e-300; it would be 0 in double precision)",
                      "constants must be finite real numbers within the double range")
        # Exact rationals keep symbolic results clean (0.5 -> 1/2).
        return sp.Rational(literal.replace("_", "")) if _is_plain_decimal(literal) else sp.Float(value)

    def _Name(self, node: ast.Name) -> sp.Expr:
        name = node.id
        if name.startswith("__"):
            self.fail(f"dunder name '{name}' is not allowed")
        if name in self.scope.names:
            return self.scope.names[name]
        if name == "t":
            return self.scope.t
        if name in FUNCTIONS:
            self.fail(f"'{name}' is a function; call it as {name}(...)")
        if name in self.scope.elsewhere:
            self.fail(*self.scope.elsewhere[name])
        close = difflib.get_close_matches(name, list(self.scope.names) + ["t"], n=3)
        self.fail(f"unknown name '{name}'",
                  f"did you mean {' or '.join(repr(c) for c in close)}?" if close
                  else "names must be coordinates, their `_dot` velocities, parameters, "
                       "known functions, earlier definitions, t or pi")

    def _UnaryOp(self, node: ast.UnaryOp) -> sp.Expr:
        return self.unary(node.op, self.scalar(node.operand))

    def unary(self, op: ast.unaryop, operand: sp.Expr) -> sp.Expr:
        if isinstance(op, ast.USub):
            # -(a chain's sum of n terms): not sorted by compare, its negated terms the same
            # objects from one position to the next (the memos below find them by identity)
            return negative(operand, self.scope.memo.setdefault("negated", {}))
        if isinstance(op, ast.UAdd):
            return operand
        self.fail(f"operator '{type(op).__name__}' is not allowed")

    def _BinOp(self, node: ast.BinOp) -> sp.Expr:
        if _is_sum(node):
            return self._sum(node)
        return self.binary(node.op, self.scalar(node.left), self.scalar(node.right))

    def _sum(self, node: ast.BinOp):
        """a + b - c + ...: Python's tree nests a sum of n terms n deep; walked down in a
        loop, its terms built left to right and added at once (`add`: a report's sum can
        have thousands of terms, and adding them one by one costs n^2)."""
        top, operands, negated = node, [], []
        while _is_sum(node):
            operands.append(node.right)
            negated.append(isinstance(node.op, ast.Sub))
            node = node.left
        operands.append(node)
        negated.append(False)
        operands.reverse()
        negated.reverse()
        return self.guarded(self.add([self.term(n) for n in operands], operands, negated), top)

    def term(self, node: ast.AST):
        """`build(node)` of a sum's term, remembered in the scope by its text while the names
        it uses stand for the same values: a chain's k-th position repeats the k - 1 terms
        of the one before it, and building them anew was most of reading the spec. The same
        value: a term's value depends on its text and on those names only (errors, which
        also quote the whole expression, are never remembered)."""
        text = self.segment(node)
        if text is None:
            return self.build(node)
        key, names = (type(self), text), self.scope.names
        found = self.scope.built.get(key)
        if found is not None:
            used, values, value = found
            if all(names.get(name) is was for name, was in zip(used, values)):
                return value
        value = self.build(node)
        used = tuple(dict.fromkeys(n.id for n in ast.walk(node) if isinstance(n, ast.Name)))
        self.scope.built[key] = (used, tuple(names.get(name) for name in used), value)
        return value

    def add(self, values: list, nodes: list[ast.AST], negated: list[bool]):
        """The sum of the terms `values` (written at `nodes`; those `negated` subtracted)."""
        terms = [self.as_scalar(v, n) for v, n in zip(values, nodes)]
        return total([negative(term) if minus else term for term, minus in zip(terms, negated)])

    def as_scalar(self, value, node: ast.AST | None = None):
        """`value`, which must be a scalar (every value here; vectors.py checks it)."""
        return value

    def binary(self, op_node: ast.operator, left: sp.Expr, right: sp.Expr) -> sp.Expr:
        if isinstance(op_node, ast.Pow):
            return self._power(left, right)
        op = _BINARY.get(type(op_node))
        if op is None:
            self.fail(f"operator '{type(op_node).__name__}' is not allowed")
        if isinstance(op_node, ast.Div) and self.is_zero(right):
            self.fail("division by zero")
        return op(left, right)

    def _power(self, base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
        if exponent.is_Number:
            if abs(exponent) > MAX_EXPONENT:
                self.fail(f"exponent {_number_text(exponent)} is too large (at most {MAX_EXPONENT})")
            if base.is_Rational and exponent.is_Integer and \
                    exact_digits(base) * abs(int(exponent)) > MAX_EXACT_NUMBER_DIGITS:
                self.too_many_digits(exact_digits(base) * abs(int(exponent)))
            size = abs(constant_value(base, self.values)) if self.is_constant(base) else 0.0
            if size != 0 and abs(float(exponent) * math.log10(size)) > 300:
                self.fail("numeric power is too large or too small for double precision")
            if self.is_zero(base) and exponent.is_negative:
                self.fail("division by zero (0 to a negative power)")
            if base.is_Rational and not exponent.is_Integer and \
                    (exact_digits(base) > MAX_EXACT_DIGITS or exponent.is_Rational and exponent.q > MAX_EXACT_ROOT):
                # sympy factors the integers of an exact root (to pull out perfect powers) and raises
                # them to the exponent's numerator first: unbounded work for big numbers or roots of
                # a high degree (12**-0.007 is a 1000th root), so those are taken in floating point
                base = sp.Float(base, 17)
        result = base ** exponent
        # sympy merges (x**a)**b into x**(a*b): bound the merged exponent too
        if result.is_Pow and result.exp.is_Number and abs(result.exp) > MAX_EXPONENT:
            self.fail(f"exponent {_number_text(result.exp)} is too large (at most {MAX_EXPONENT})")
        if result.has(sp.I, sp.zoo, sp.nan, sp.oo):
            self.fail("the expression is complex or infinite; expressions must be real")
        return result

    def _Call(self, node: ast.Call) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            self.build(node.func)  # names the forbidden construct (lambda, attribute ...) if any
            self.fail("calling an expression is not allowed; only plain function calls like sin(x)")
        name = node.func.id
        if name.startswith("__"):
            self.fail(f"dunder name '{name}' is not allowed")
        if name not in FUNCTIONS:
            hint = difflib.get_close_matches(name, list(FUNCTIONS), n=1)
            self.fail(f"unknown function '{name}'",
                      f"did you mean '{hint[0]}'?" if hint else "functions: " + ", ".join(sorted(FUNCTIONS)))
        if node.keywords:
            self.fail(f"keyword arguments are not allowed in {name}(...)")
        constructor, low, high = FUNCTIONS[name]
        if not low <= len(node.args) <= high:
            count = str(low) if low == high else f"{low} to {high}"
            self.fail(f"{name}() takes {count} argument(s), got {len(node.args)}")
        if name == "diff":
            return self._diff(node)
        if name == "sqrt":  # sqrt(a) is a ** (1/2): the same checks
            return self._power(self.scalar(node.args[0]), sp.S.Half)
        args = [self.scalar(arg) for arg in node.args]
        if max(self.depth(arg) for arg in args) >= MAX_RESULT_DEPTH:
            self.too_deep()  # before sympy evaluates the call: sin(sin(...(1/2))) grows costly
        try:
            if constructor in TRIG:     # sin(q3): sympy's call, without its evaluation's tests
                return trig_call(constructor, args[0])
            return constructor(*args)
        except (ValueError, TypeError, ArithmeticError) as exc:  # e.g. Min of incomparable arguments
            self.fail(f"cannot apply {name}() to these arguments ({exc})")

    def _diff(self, node: ast.Call) -> sp.Expr:
        variable = node.args[1]
        if not (isinstance(variable, ast.Name) and variable.id == "t"):
            self.fail("diff(expr, t) differentiates with respect to time t only")
        if self.scope.time_derivative is None:
            self.fail("diff(expr, t) is not available here")
        return self.scope.time_derivative(self.scalar(node.args[0]))


def exact_digits(number: sp.Rational) -> int:
    """About how many decimal digits the longer of the numerator and denominator has (no
    conversion to text: Python refuses to print an integer of over 4300 digits)."""
    return 1 + int(max(abs(number.p).bit_length(), number.q.bit_length()) * 0.30103)


def _number_text(number: sp.Number) -> str:
    """A number for a message: exact when short, else its floating-point value."""
    if number.is_Rational and exact_digits(number) > 20:
        value = float(number)
        if math.isfinite(value) and value != 0:
            return f"{value:.6g}"
        exponent = (abs(number.p).bit_length() - number.q.bit_length()) * 0.30103
        return f"of about {'-' if number.p < 0 else ''}1e{round(exponent):+d}"
    return _short(str(number))  # a Float, or a short exact number


def _literal_exponent(literal: str) -> int:
    """|e| of a literal written 1.5e-7 (0 without an exponent)."""
    mantissa, e, exponent = literal.lower().replace("_", "").partition("e")
    if not e or "x" in mantissa:
        return 0
    digits = exponent.lstrip("+-")
    return MAX_LITERAL_EXPONENT + 1 if len(digits) > 6 else int(digits or 0)


def _is_plain_decimal(literal: str) -> bool:
    body = literal.replace("_", "")
    return all(c.isdigit() or c in ".eE+-" for c in body)


def _short(text: str, width: int = 60) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _fail(loc: Loc, message: str, hint: str = "") -> None:
    raise SpecError(Problem(loc, message, hint))
