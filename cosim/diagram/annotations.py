"""The Modelica source as the graphical annotations need it.

pymoca's AST keeps a class's annotation but drops the annotations of component declarations and
of ``connect`` equations, where the placements and connection lines of MLS chapter 18 are. This
module reads the source text itself:

- :func:`tokenize`: Modelica's lexical units with their line and column;
- :func:`parse_file`: the classes a file defines (nested ones too), each with its ``extends``
  clauses, its component declarations (name, type, prefixes, modifiers, annotation), its
  ``connect`` equations (with their annotation) and its class annotation; everything else
  (equations, algorithms, expressions) is skipped;
- :class:`Annotation`: an ``annotation(...)`` clause whose top-level arguments (``Icon``,
  ``Placement``, ``Line``, ...) are parsed on demand into Python values (:class:`Record`,
  :class:`Name`, lists, numbers, strings, booleans) by a parser of Modelica expressions, so that a
  vendor annotation that is not drawn is never an error.

Errors name ``file:line:col`` (:class:`~cosim.errors.ModelicaError`).
"""
from __future__ import annotations

import bisect
import math
import os
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from cosim.errors import ModelicaError

CLASS_KINDS = frozenset({"class", "model", "record", "block", "connector", "type", "package", "function",
                         "operator"})
KIND_PREFIXES = frozenset({"expandable", "pure", "impure", "operator"})
ELEMENT_PREFIXES = frozenset({"redeclare", "final", "inner", "outer", "replaceable", "encapsulated", "partial"})
TYPE_PREFIXES = frozenset({"flow", "stream", "discrete", "parameter", "constant", "input", "output"})
STATEMENT_KEYWORDS = frozenset({"for", "if", "when", "while"})
# identifiers that cannot end an operand (an expression continues after them)
OPERATOR_WORDS = frozenset({"and", "or", "not", "if", "then", "else", "elseif", "in", "for", "loop"})

_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:[^"\\]|\\.)*")
  | (?P<qident>'(?:[^'\\]|\\.)*')
  | (?P<number>(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<ident>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>\.\^|\.\*|\./|\.\+|\.-|<=|>=|==|<>|:=|[-+*/^=<>(){}\[\],;:.])
""", re.VERBOSE | re.DOTALL)

_OPEN = {"(": ")", "[": "]", "{": "}"}
_CLOSE = {")", "]", "}"}


@dataclass(frozen=True)
class Token:
    """One lexical unit: ``kind`` is ident, qident, number, string or op; ``text`` as written."""

    kind: str
    text: str
    start: int
    end: int
    line: int
    col: int

    def is_word(self, word: str) -> bool:
        """True for the identifier ``word``."""
        return self.kind == "ident" and self.text == word


class Source:
    """The text and tokens of one Modelica file.

    Parameters
    ----------
    file : Path
        Where the text comes from (named in errors).
    text : str
        The file's text.
    """

    def __init__(self, file: Path, text: str):
        self.file = Path(file)
        self.text = text
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        self.tokens = tokenize(self)

    def position(self, offset: int) -> tuple[int, int]:
        """1-based ``(line, column)`` of the character at ``offset``."""
        line = bisect.bisect_right(self._line_starts, offset)
        return line, offset - self._line_starts[line - 1] + 1

    def where(self, token: Token | None, column: bool = True) -> str:
        """``file:line:col`` of ``token`` (the end of the file for None)."""
        if token is None:
            line, col = self.position(len(self.text))
        else:
            line, col = token.line, token.col
        return f"{self.file}:{line}:{col}" if column else f"{self.file}:{line}"

    def error(self, token: Token | None, message: str) -> ModelicaError:
        """A ModelicaError ``file:line:col: message`` at ``token``."""
        return ModelicaError(f"{self.where(token)}: {message}")

    def between(self, first: Token, last: Token) -> str:
        """The source text from ``first`` to ``last`` (inclusive), whitespace runs made one space
        outside strings."""
        parts = re.split(r'("(?:[^"\\]|\\.)*")', self.text[first.start:last.end])
        return "".join(p if k % 2 else re.sub(r"\s+", " ", p) for k, p in enumerate(parts)).strip()


def tokenize(source: Source) -> list[Token]:
    """The tokens of ``source`` (whitespace and comments dropped).

    Raises
    ------
    ModelicaError
        ``file:line:col`` of an unterminated string or comment, or a character that is no part
        of Modelica.
    """
    text, tokens, pos = source.text, [], 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None:
            line, col = source.position(pos)
            what = ("unterminated string" if text[pos] == '"' else "unterminated comment /*"
                    if text.startswith("/*", pos) else f"unexpected character {text[pos]!r}")
            raise ModelicaError(f"{source.file}:{line}:{col}: {what}")
        kind = match.lastgroup
        if kind not in ("space", "comment"):
            line, col = source.position(pos)
            tokens.append(Token(kind, match.group(), pos, match.end(), line, col))
        pos = match.end()
    return tokens


# --------------------------------------------------------------------------- values

@dataclass(frozen=True)
class Name:
    """A name in an annotation that is not a call: an enumeration literal such as
    ``FillPattern.Solid``, or a reference to a variable."""

    name: str

    @property
    def last(self) -> str:
        """The last part of the name (``Solid`` of ``FillPattern.Solid``)."""
        return self.name.rsplit(".", 1)[-1]


@dataclass(frozen=True)
class Expression:
    """An expression the parser does not evaluate (a variable, a comparison, ``if``), as text."""

    text: str


@dataclass(frozen=True)
class Record:
    """A record constructor ``Name(arg = value, ...)`` or a modification ``name(arg = value, ...)``.

    Attributes
    ----------
    name : str
        The record's (or modified element's) name as written.
    arguments : dict
        Named arguments -> values.
    positional : tuple
        Positional arguments (record constructors only).
    line : int
        Where the record starts in its file.
    """

    name: str
    arguments: dict = field(default_factory=dict)
    positional: tuple = ()
    line: int = 0

    def get(self, key: str, default=None):
        """The named argument ``key``, else ``default``."""
        return self.arguments.get(key, default)


_ESCAPES = {'"': '"', "'": "'", "\\": "\\", "?": "?", "a": "\a", "b": "\b", "f": "\f", "n": "\n", "r": "\r",
            "t": "\t", "v": "\v"}


def string_value(token_text: str) -> str:
    """The value of a Modelica string literal (quotes removed, escape sequences applied)."""
    return re.sub(r"\\(.)", lambda m: _ESCAPES.get(m.group(1), m.group(1)), token_text[1:-1], flags=re.DOTALL)


class _ExpressionParser:
    """Modelica expressions of annotations, on the tokens ``tokens[start:stop]`` of ``source``."""

    _BINARY = {"or": 1, "and": 2, "<": 3, "<=": 3, ">": 3, ">=": 3, "==": 3, "<>": 3,
               "+": 4, "-": 4, ".+": 4, ".-": 4, "*": 5, "/": 5, ".*": 5, "./": 5, "^": 6, ".^": 6}

    def __init__(self, source: Source, start: int, stop: int):
        self.source, self.tokens, self.i, self.stop = source, source.tokens, start, stop

    def peek(self, k: int = 0) -> Token | None:
        return self.tokens[self.i + k] if self.i + k < self.stop else None

    def at(self, text: str, k: int = 0) -> bool:
        token = self.peek(k)
        return token is not None and token.kind in ("op", "ident") and token.text == text

    def advance(self) -> Token:
        token = self.peek()
        if token is None:
            end = self.tokens[self.stop] if self.stop < len(self.tokens) else None
            raise self.source.error(end, f"annotation: a value is missing before '{end.text}'" if end else
                                    "annotation: a value is missing at the end")
        self.i += 1
        return token

    def separator(self) -> None:
        """A ``,`` between two items (none after the last)."""
        self.expect(",")
        if self.peek() is None:
            self.advance()  # raises: a value is missing

    def expect(self, text: str) -> Token:
        token = self.peek()
        if token is None or token.text != text or token.kind not in ("op", "ident"):
            found = f"'{token.text}'" if token else "the end of the annotation"
            raise self.source.error(token or (self.tokens[self.stop] if self.stop < len(self.tokens) else None),
                                    f"annotation: expected '{text}', found {found}")
        self.i += 1
        return token

    def text_from(self, first: int) -> str:
        return self.source.between(self.tokens[first], self.tokens[self.i - 1])

    # -- modifications ---------------------------------------------------------------------
    def modification_arguments(self) -> dict:
        """``name [(...)] [= expr], ...`` up to the end of the slice: name -> value."""
        found = {}
        while self.peek() is not None:
            name, value = self.argument()
            found[name] = value
            if self.peek() is not None:
                self.separator()
        return found

    def argument(self) -> tuple[str, object]:
        """One element of a class modification (``each``/``final`` ignored)."""
        while self.at("each") or self.at("final"):
            self.advance()
        token = self.advance()
        if token.kind not in ("ident", "qident"):
            raise self.source.error(token, f"annotation: expected a name, found '{token.text}'")
        name = token.text
        while self.at(".") and self.peek(1) is not None and self.peek(1).kind == "ident":
            self.advance()
            name += "." + self.advance().text
        value = None
        if self.at("("):
            self.advance()
            close = self.matching(self.i - 1)
            inner = _ExpressionParser(self.source, self.i, close)
            value = Record(name, inner.modification_arguments(), line=token.line)
            self.i = close + 1
        if self.at("=") or self.at(":="):
            self.advance()
            value = self.expression()
        while self.peek() is not None and self.peek().kind == "string":  # a description string
            self.advance()
        return name, value

    def matching(self, open_index: int) -> int:
        """Index of the bracket that closes the one at ``open_index`` (within the slice)."""
        return matching_bracket(self.source, open_index, self.stop)

    # -- expressions -----------------------------------------------------------------------
    def expression(self):
        first = self.i
        if self.at("if"):
            while self.peek() is not None and not (self.at(",") or self.at(";")):
                token = self.advance()
                if token.text in _OPEN and token.kind == "op":
                    self.i = self.matching(self.i - 1) + 1
            return Expression(self.text_from(first))
        return self.binary(0)

    def binary(self, level: int):
        first = self.i
        if self.at("-") or self.at("+"):
            sign = self.advance().text
            operand = self.binary(5)
            value = _negate(operand) if sign == "-" else operand
            if value is None:
                value = Expression(self.text_from(first))
        elif self.at("not"):
            self.advance()
            self.binary(3)
            value = Expression(self.text_from(first))
        else:
            value = self.primary()
        while True:
            token = self.peek()
            precedence = self._BINARY.get(token.text) if token is not None and token.kind in ("op", "ident") else None
            if precedence is None or precedence <= level:
                return value
            self.advance()
            right = self.binary(precedence if token.text not in ("^", ".^") else precedence - 1)
            result = _arithmetic(token.text, value, right)
            value = Expression(self.text_from(first)) if result is None else result

    def primary(self):
        token = self.advance()
        if token.kind == "number":
            text = token.text
            return int(text) if re.fullmatch(r"\d+", text) else float(text)
        if token.kind == "string":
            return string_value(token.text)
        if token.kind == "op" and token.text == "{":
            return self.array(token)
        if token.kind == "op" and token.text == "[":
            return self.matrix(token)
        if token.kind == "op" and token.text == "(":
            value = self.expression()
            self.expect(")")
            return value
        if token.is_word("true") or token.is_word("false"):
            return token.text == "true"
        if token.kind in ("ident", "qident") or (token.kind == "op" and token.text == "."):
            return self.name_or_call(token)
        if token.kind == "op" and token.text == ":":
            return Expression(":")
        raise self.source.error(token, f"annotation: unexpected '{token.text}' in an expression")

    def name_or_call(self, token: Token):
        first = self.i - 1
        name = token.text if token.text != "." else ""
        if token.text == ".":
            name = self.advance().text
        subscripted = False
        while True:
            if self.at("["):
                self.i = self.matching(self.i) + 1
                subscripted = True
            elif self.at(".") and self.peek(1) is not None and self.peek(1).kind in ("ident", "qident"):
                self.advance()
                name += "." + self.advance().text
            else:
                break
        if self.at("(") and not subscripted:
            open_index = self.i
            close = self.matching(open_index)
            inner = _ExpressionParser(self.source, open_index + 1, close)
            positional, named = inner.call_arguments()
            self.i = close + 1
            if name in ("DynamicSelect", "Modelica.DynamicSelect") and positional:
                return positional[0]  # the static value
            return Record(name, named, tuple(positional), token.line)
        if subscripted:
            return Expression(self.text_from(first))
        return Name(name)

    def call_arguments(self) -> tuple[list, dict]:
        positional, named = [], {}
        while self.peek() is not None:
            token = self.peek()
            if token.kind == "ident" and self.at("=", 1):
                self.advance()
                self.advance()
                named[token.text] = self.expression()
            else:
                start = self.i
                value = self.expression()
                if self.at("for"):  # a reduction or comprehension: not evaluated
                    while self.peek() is not None and not self.at(","):
                        self.advance()
                    value = Expression(self.text_from(start))
                positional.append(value)
            if self.peek() is not None:
                self.separator()
        return positional, named

    def array(self, open_token: Token):
        close = self.matching(self.i - 1)
        inner = _ExpressionParser(self.source, self.i, close)
        items = []
        while inner.peek() is not None:
            items.append(inner.expression())
            if inner.at("for"):
                self.i = close + 1
                return Expression(self.source.between(open_token, self.tokens[close]))
            if inner.peek() is not None:
                inner.separator()
        self.i = close + 1
        return items

    def matrix(self, open_token: Token):
        close = self.matching(self.i - 1)
        inner = _ExpressionParser(self.source, self.i, close)
        rows, row = [], []
        while inner.peek() is not None:
            row.append(inner.expression())
            if inner.at(";"):
                inner.advance()
                rows.append(row)
                row = []
            elif inner.peek() is not None:
                inner.expect(",")
        rows.append(row)
        self.i = close + 1
        return rows


def _negate(value):
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return -value
    if isinstance(value, list):
        items = [_negate(v) for v in value]
        return None if any(v is None for v in items) else items
    return None


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _arithmetic(operator: str, left, right):
    """``left operator right`` for numbers, strings (``+``) and arrays (elementwise ``+ -``,
    scaled by a number); None where the parser does not evaluate it."""
    op = operator.lstrip(".")
    if _is_number(left) and _is_number(right):
        try:
            if op == "+":
                return left + right
            if op == "-":
                return left - right
            if op == "*":
                return left * right
            if op == "/":
                return left / right if right != 0 else None
            if op == "^":
                result = float(left) ** right
                return result if isinstance(result, float) and math.isfinite(result) else None
        except (OverflowError, ZeroDivisionError, ValueError):
            return None
        return None
    if op == "+" and isinstance(left, str) and isinstance(right, str):
        return left + right
    if isinstance(left, list) and isinstance(right, list) and op in ("+", "-") and len(left) == len(right):
        items = [_arithmetic(op, a, b) for a, b in zip(left, right)]
        return None if any(v is None for v in items) else items
    if op in ("*", "/") and isinstance(left, list) and _is_number(right):
        items = [_arithmetic(op, a, right) for a in left]
        return None if any(v is None for v in items) else items
    if op == "*" and _is_number(left) and isinstance(right, list):
        items = [_arithmetic(op, left, b) for b in right]
        return None if any(v is None for v in items) else items
    return None


def matching_bracket(source: Source, open_index: int, stop: int | None = None) -> int:
    """Index of the token that closes the bracket at ``open_index``.

    Raises
    ------
    ModelicaError
        At the opening bracket if it is not closed, or at a closing bracket of the wrong kind.
    """
    tokens = source.tokens
    stop = len(tokens) if stop is None else stop
    stack = [tokens[open_index]]
    for k in range(open_index + 1, stop):
        token = tokens[k]
        if token.kind != "op":
            continue
        if token.text in _OPEN:
            stack.append(token)
        elif token.text in _CLOSE:
            opened = stack.pop()
            if _OPEN[opened.text] != token.text:
                raise source.error(token, f"'{token.text}' does not close '{opened.text}' of line {opened.line}")
            if not stack:
                return k
    raise source.error(stack[-1], f"'{stack[-1].text}' is not closed")


def parse_expression(source: Source, start: int, stop: int):
    """The value of the expression ``tokens[start:stop]`` of ``source``.

    Raises
    ------
    ModelicaError
        ``file:line:col`` of a token that does not fit, or of tokens left over.
    """
    parser = _ExpressionParser(source, start, stop)
    try:
        value = parser.expression()
    except RecursionError:
        raise source.error(source.tokens[start], "annotation: the expression is nested too deeply") from None
    if parser.peek() is not None:
        raise source.error(parser.peek(), f"annotation: unexpected '{parser.peek().text}' after an expression")
    return value


# --------------------------------------------------------------------------- annotations

@dataclass
class Annotation:
    """An ``annotation(...)`` clause.

    Attributes
    ----------
    source : Source
        The file it is in.
    line : int
        Its line.
    spans : dict
        Top-level argument name -> ``(start, stop)`` token indices of the argument; its value is
        parsed by :meth:`get` when asked for.
    """

    source: Source
    line: int
    spans: dict

    @property
    def where(self) -> str:
        """``file:line`` of the clause."""
        return f"{self.source.file}:{self.line}"

    def __contains__(self, name: str) -> bool:
        return name in self.spans

    def get(self, name: str):
        """The value of the top-level argument ``name`` (a :class:`Record` for ``name(...)``, else
        the value after ``=``), None if there is none.

        Raises
        ------
        ModelicaError
            If the argument is malformed (``file:line:col``).
        """
        span = self.spans.get(name)
        if span is None:
            return None
        parser = _ExpressionParser(self.source, *span)
        try:
            _, value = parser.argument()
        except RecursionError:
            raise self.source.error(self.source.tokens[span[0]], f"annotation: {name}(...) is nested too deeply") \
                from None
        if parser.peek() is not None:
            raise self.source.error(parser.peek(), f"annotation: unexpected '{parser.peek().text}' in {name}(...)")
        return value


def _split_arguments(source: Source, start: int, stop: int) -> list[tuple[int, int]]:
    """Token spans of the comma-separated arguments in ``tokens[start:stop]`` (brackets nested)."""
    spans, first, k = [], start, start
    tokens = source.tokens
    while k < stop:
        token = tokens[k]
        if token.kind == "op" and token.text in _OPEN:
            k = matching_bracket(source, k, stop)
        elif token.kind == "op" and token.text == ",":
            spans.append((first, k))
            first = k + 1
        k += 1
    if first < stop:
        spans.append((first, stop))
    elif spans:  # a trailing comma
        raise source.error(tokens[stop - 1], "annotation: an argument is missing after ','")
    return spans


def _argument_name(source: Source, start: int, stop: int) -> tuple[str, int]:
    """The (dotted) name an argument ``[each] [final] name ...`` modifies and the index after it."""
    tokens, k = source.tokens, start
    while k < stop and (tokens[k].is_word("each") or tokens[k].is_word("final")):
        k += 1
    if k >= stop or tokens[k].kind not in ("ident", "qident"):
        token = tokens[k] if k < stop else tokens[start]
        raise source.error(token, f"expected a name in a modification, found '{token.text}'")
    name = tokens[k].text
    k += 1
    while k + 1 < stop and tokens[k].text == "." and tokens[k + 1].kind in ("ident", "qident"):
        name += "." + tokens[k + 1].text
        k += 2
    return name, k


# --------------------------------------------------------------------------- classes

@dataclass
class Component:
    """One component declaration.

    Attributes
    ----------
    name, type : str
        The component's name and its type as written (``Bicycle.Interfaces.RealInput``).
    line : int
        The line of the declaration.
    prefixes : frozenset of str
        ``parameter``, ``input``, ``replaceable``, ``redeclare``, ... as written.
    protected : bool
        Declared in a protected section.
    modifiers : dict of str to str
        The top-level modifiers of the declaration, name -> the source text of the value.
    binding : str or None
        The source text of the declaration equation (``= expr``).
    annotation : Annotation or None
        Its ``annotation(...)``.
    """

    name: str
    type: str
    line: int
    prefixes: frozenset = frozenset()
    protected: bool = False
    modifiers: dict = field(default_factory=dict)
    binding: str | None = None
    annotation: Annotation | None = None


@dataclass
class Extends:
    """An ``extends`` clause: the base class as written, the values it modifies, the components
    it redeclares (name -> type) and its annotation (``IconMap``, ``DiagramMap``)."""

    name: str
    line: int
    modifiers: dict = field(default_factory=dict)
    redeclares: dict = field(default_factory=dict)
    annotation: Annotation | None = None


@dataclass
class Connection:
    """A ``connect(a, b)`` equation, its connectors as written and its annotation."""

    a: str
    b: str
    line: int
    annotation: Annotation | None = None


@dataclass
class ClassDef:
    """A class as defined in a file.

    Attributes
    ----------
    name : str
        The short name.
    kind : str
        ``model``, ``block``, ``connector``, ``package``, ...
    partial : bool
        Declared partial.
    source : Source
        The file.
    line : int
        The line of the definition.
    base : str or None
        For a short class definition ``connector X = input Real``: the class it stands for.
    extends, components, connections : list
        What the class declares itself (not what it inherits).
    classes : dict of str to ClassDef
        Its nested classes.
    annotation : Annotation or None
        The class annotation.
    """

    name: str
    kind: str
    partial: bool
    source: Source
    line: int
    base: str | None = None
    base_modifiers: dict = field(default_factory=dict)
    extends: list = field(default_factory=list)
    components: list = field(default_factory=list)
    connections: list = field(default_factory=list)
    classes: dict = field(default_factory=dict)
    annotation: Annotation | None = None

    @property
    def where(self) -> str:
        """``file:line`` of the definition."""
        return f"{self.source.file}:{self.line}"


@dataclass
class SourceFile:
    """A parsed file: its ``within`` prefix and the classes it defines."""

    source: Source
    within: str
    classes: dict


class _ClassParser:
    """The structure of class definitions, on the tokens of one file."""

    def __init__(self, source: Source):
        self.source, self.tokens, self.i = source, source.tokens, 0

    # -- tokens ----------------------------------------------------------------------------
    def peek(self, k: int = 0) -> Token | None:
        return self.tokens[self.i + k] if self.i + k < len(self.tokens) else None

    def at(self, text: str, k: int = 0) -> bool:
        token = self.peek(k)
        return token is not None and token.kind in ("op", "ident") and token.text == text

    def advance(self) -> Token:
        token = self.peek()
        if token is None:
            raise self.source.error(None, "unexpected end of the file")
        self.i += 1
        return token

    def expect(self, text: str, what: str = "") -> Token:
        token = self.peek()
        if token is None or token.text != text or token.kind not in ("op", "ident"):
            found = f"'{token.text}'" if token else "the end of the file"
            raise self.source.error(token, f"expected '{text}'{what}, found {found}")
        self.i += 1
        return token

    def identifier(self, what: str) -> Token:
        token = self.peek()
        if token is None or token.kind not in ("ident", "qident"):
            found = f"'{token.text}'" if token else "the end of the file"
            raise self.source.error(token, f"expected {what}, found {found}")
        self.i += 1
        return token

    def skip_group(self) -> None:
        """Skip the bracketed group that starts at the current token."""
        self.i = matching_bracket(self.source, self.i) + 1

    # -- file ------------------------------------------------------------------------------
    def file(self) -> SourceFile:
        within = ""
        if self.at("within"):
            self.advance()
            if not self.at(";"):
                within = self.type_name()
            self.expect(";")
        classes = {}
        while self.peek() is not None:
            prefixes = self.prefixes(ELEMENT_PREFIXES)
            cls = self.class_definition(prefixes)
            classes[cls.name] = cls
            self.expect(";", f" after 'end {cls.name}'")
        return SourceFile(self.source, within, classes)

    def prefixes(self, allowed: frozenset) -> set:
        found = set()
        while self.peek() is not None and self.peek().kind == "ident" and self.peek().text in allowed:
            found.add(self.advance().text)
        return found

    def at_class(self) -> bool:
        token = self.peek()
        return token is not None and token.kind == "ident" and (
            token.text in CLASS_KINDS or token.text in KIND_PREFIXES)

    def type_name(self) -> str:
        name = ""
        if self.at("."):
            self.advance()
            name = "."
        name += self.identifier("a name").text
        while self.at(".") and self.peek(1) is not None and self.peek(1).kind in ("ident", "qident"):
            self.advance()
            name += "." + self.advance().text
        return name.lstrip(".")

    def comment(self) -> str:
        text = ""
        while self.peek() is not None and self.peek().kind == "string":
            text += string_value(self.advance().text)
            if self.at("+") and self.peek(1) is not None and self.peek(1).kind == "string":
                self.advance()
        return text

    def annotation(self) -> Annotation | None:
        if not self.at("annotation"):
            return None
        keyword = self.advance()
        if not self.at("("):
            raise self.source.error(self.peek(), "expected '(' after 'annotation'")
        close = matching_bracket(self.source, self.i)
        spans = {}
        for start, stop in _split_arguments(self.source, self.i + 1, close):
            name, _ = _argument_name(self.source, start, stop)
            spans[name] = (start, stop)
        self.i = close + 1
        return Annotation(self.source, keyword.line, spans)

    # -- classes ---------------------------------------------------------------------------
    def class_definition(self, prefixes: set) -> ClassDef:
        start = self.peek()
        kind = None
        while self.at_class():
            word = self.advance().text
            if word in CLASS_KINDS:
                kind = word
            if word in ("pure", "impure"):
                kind = "function"
        if kind is None:
            token = self.peek()
            found = f"'{token.text}'" if token else "the end of the file"
            raise self.source.error(token, f"expected a class definition (model, block, connector, ...), found {found}")
        class_extends = False
        if self.at("extends"):  # `model extends Name`: a redefinition of an inherited class
            self.advance()
            class_extends = True
        name_token = self.identifier("the name of the class")
        cls = ClassDef(name_token.text, kind, "partial" in prefixes, self.source, start.line)
        if self.at("=") and not class_extends:
            self.advance()
            self.short_definition(cls)
            return cls
        if class_extends and self.at("("):
            self.skip_group()
        self.comment()
        self.composition(cls)
        self.expect("end")
        end_name = self.identifier(f"'{cls.name}' after 'end'")
        if end_name.text != cls.name:
            raise self.source.error(end_name, f"'end {end_name.text}' closes class '{cls.name}' "
                                              f"of line {cls.line}")
        return cls

    def short_definition(self, cls: ClassDef) -> None:
        if self.at("enumeration") or self.at("der"):
            self.advance()
            if self.at("("):
                self.skip_group()
        else:
            self.prefixes(TYPE_PREFIXES)
            cls.base = self.type_name()
            if self.at("["):
                self.skip_group()
            if self.at("("):
                cls.base_modifiers, _ = self.modifiers()
        self.comment()
        cls.annotation = self.annotation() or cls.annotation

    def composition(self, cls: ClassDef) -> None:
        section, protected = "element", False
        while True:
            token = self.peek()
            if token is None:
                raise self.source.error(self.tokens[-1] if self.tokens else None,
                                        f"class '{cls.name}' of line {cls.line} has no 'end {cls.name};'")
            if token.is_word("end") and self.peek(1) is not None and self.peek(1).kind in ("ident", "qident") \
                    and self.peek(1).text not in STATEMENT_KEYWORDS:
                return
            if token.is_word("public") or token.is_word("protected"):
                self.advance()
                section, protected = "element", token.text == "protected"
            elif token.is_word("initial") and (self.at("equation", 1) or self.at("algorithm", 1)):
                self.i += 2
                section = "equation"
            elif token.is_word("equation") or token.is_word("algorithm"):
                self.advance()
                section = "equation"
            elif token.is_word("external"):
                self.statement_end()
            elif token.is_word("annotation"):
                cls.annotation = self.annotation()
                self.expect(";", " after the class annotation")
            elif section == "equation":
                self.equation(cls)
            else:
                self.element(cls, protected)

    def statement_end(self) -> None:
        """Skip to the ``;`` that ends the current statement (brackets nested)."""
        while not self.at(";"):
            if self.peek() is None:
                raise self.source.error(None, "expected ';'")
            if self.peek().kind == "op" and self.peek().text in _OPEN:
                self.skip_group()
            else:
                self.advance()
        self.advance()

    def equation(self, cls: ClassDef) -> None:
        """One equation or statement; ``connect(a, b) annotation(...)`` is kept. The bodies of
        ``for``/``if``/``when`` are read statement by statement, so connects inside count."""
        token = self.peek()
        if token.is_word("connect") and self.at("(", 1):
            self.advance()
            close = matching_bracket(self.source, self.i)
            spans = _split_arguments(self.source, self.i + 1, close)
            if len(spans) != 2:
                raise self.source.error(token, "connect(a, b) takes two connectors")
            a, b = (self.source.between(self.tokens[s], self.tokens[e - 1]).replace(" ", "") for s, e in spans)
            self.i = close + 1
            self.comment()
            annotation = self.annotation()
            self.expect(";", " after connect(...)")
            cls.connections.append(Connection(a, b, token.line, annotation))
            return
        if token.kind == "ident" and token.text in STATEMENT_KEYWORDS:  # its header up to loop/then
            self.advance()
            self._skip_past(token, ("loop", "then"))
            return
        if token.is_word("else"):
            self.advance()
            return
        if token.is_word("elseif") or token.is_word("elsewhen"):
            self._skip_past(token, ("then",))
            return
        self.statement_end()

    def _skip_past(self, token, words: tuple) -> None:
        """Skip the header of ``token``'s statement up to and including the first of ``words``
        (brackets skipped whole)."""
        while not any(self.at(w) for w in words):
            if self.peek() is None:
                raise self.source.error(token, f"'{token.text}' without " + " or ".join(f"'{w}'" for w in words))
            if self.peek().kind == "op" and self.peek().text in _OPEN:
                self.skip_group()
            else:
                self.advance()
        self.advance()

    def element(self, cls: ClassDef, protected: bool) -> None:
        token = self.peek()
        if token.is_word("import"):
            self.statement_end()
            return
        if token.is_word("extends"):
            self.advance()
            name = self.type_name()
            modifiers, redeclares = self.modifiers() if self.at("(") else ({}, {})
            annotation = self.annotation()
            self.expect(";", " after the extends clause")
            cls.extends.append(Extends(name, token.line, modifiers, redeclares, annotation))
            return
        prefixes = self.prefixes(ELEMENT_PREFIXES)
        if self.at_class():
            nested = self.class_definition(prefixes)
            cls.classes[nested.name] = nested
            self.constraining_clause()
            self.expect(";", f" after the definition of '{nested.name}'")
            return
        prefixes |= self.prefixes(TYPE_PREFIXES)
        type_name = self.type_name()
        if self.at("["):
            self.skip_group()
        declared = []
        while True:
            name = self.identifier("a component name")
            if self.at("["):
                self.skip_group()
            modifiers, binding = {}, None
            if self.at("("):
                modifiers, _ = self.modifiers()
            if self.at("=") or self.at(":="):
                self.advance()
                binding = self.expression_text()
            if self.at("if"):  # condition attribute
                self.advance()
                self.expression_text()
            self.comment()
            annotation = self.annotation()
            declared.append(Component(name.text, type_name, name.line, frozenset(prefixes), protected,
                                      modifiers, binding, annotation))
            if not self.at(","):
                break
            self.advance()
        if self.at("constrainedby"):
            annotation = self.constraining_clause()
            if annotation is not None and declared[-1].annotation is None:
                declared[-1].annotation = annotation
        self.expect(";", " after the declaration")
        cls.components.extend(declared)

    def constraining_clause(self) -> Annotation | None:
        if not self.at("constrainedby"):
            return None
        self.advance()
        self.type_name()
        if self.at("("):
            self.skip_group()
        self.comment()
        return self.annotation()

    def modifiers(self) -> tuple[dict, dict]:
        """A class modification ``(...)`` at the current token: its top-level ``name = value``
        (name -> source text) and ``redeclare Type name`` (name -> type) elements."""
        close = matching_bracket(self.source, self.i)
        values, redeclares = {}, {}
        for start, stop in _split_arguments(self.source, self.i + 1, close):
            tokens = self.tokens
            if any(tokens[k].is_word("redeclare") for k in range(start, min(stop, start + 3))):
                k = start
                while k < stop and tokens[k].kind == "ident" and tokens[k].text in (
                        "redeclare", "each", "final", "replaceable"):
                    k += 1
                if k < stop and tokens[k].kind == "ident" and (tokens[k].text in CLASS_KINDS
                                                               or tokens[k].text in KIND_PREFIXES):
                    continue  # a redeclared class (package Data = ...)
                sub = _ClassParser(self.source)
                sub.i = k
                type_name = sub.type_name()
                if sub.i < stop and self.tokens[sub.i].kind in ("ident", "qident"):
                    redeclares[self.tokens[sub.i].text] = type_name
                continue
            name, k = _argument_name(self.source, start, stop)
            if k < stop and tokens[k].text == "(" and tokens[k].kind == "op":
                k = matching_bracket(self.source, k, stop) + 1
            if k < stop and tokens[k].kind == "op" and tokens[k].text in ("=", ":="):
                last = stop - 1
                while last > k + 1 and tokens[last].kind == "string" and tokens[last - 1].kind != "op":
                    last -= 1  # a description string of the modifier
                if last > k:
                    values[name] = self.source.between(tokens[k + 1], tokens[last])
        self.i = close + 1
        return values, redeclares

    def expression_text(self) -> str:
        """The source text of the expression at the current token, up to the end of the
        declaration (``,``, ``;``, a description string, ``annotation``, a condition)."""
        first, last, open_ifs = self.peek(), None, 0
        while True:
            token = self.peek()
            if token is None:
                raise self.source.error(first, "expected ';' after the expression")
            ends_operand = last is not None and (
                last.kind in ("number", "string", "qident")
                or (last.kind == "ident" and last.text not in OPERATOR_WORDS)
                or (last.kind == "op" and last.text in _CLOSE))
            if token.kind == "op" and token.text in (",", ";") or token.kind == "op" and token.text in _CLOSE:
                break
            if token.is_word("annotation") or token.is_word("constrainedby"):
                break
            if token.kind == "string" and ends_operand:
                break
            if token.is_word("if"):
                if ends_operand and open_ifs == 0:
                    break  # the condition attribute
                open_ifs += 1
            elif token.is_word("else"):
                open_ifs -= 1
            if token.kind == "op" and token.text in _OPEN:
                close = matching_bracket(self.source, self.i)
                last, self.i = self.tokens[close], close + 1
            else:
                last = self.advance()
        if last is None:
            raise self.source.error(token, f"expected an expression, found '{token.text}'")
        return self.source.between(first, last)


@lru_cache(maxsize=256)
def _parse_cached(path: str, mtime_ns: int, size: int) -> SourceFile:
    file = Path(path)
    try:
        data = file.read_bytes()
    except OSError as exc:
        raise ModelicaError(f"{file}: cannot read: {exc.strerror or exc}") from None
    try:
        text = data.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ModelicaError(f"{file}:{line}: not UTF-8 (byte offset {exc.start})") from None
    return _parse_source(Source(file, text))


def _parse_source(source: Source) -> SourceFile:
    try:
        return _ClassParser(source).file()
    except RecursionError:
        raise ModelicaError(f"{source.file}: cannot read: classes nested too deeply") from None


def parse_file(file: str | os.PathLike) -> SourceFile:
    """The classes that ``file`` defines (cached while the file is unchanged).

    Raises
    ------
    ModelicaError
        ``file:line:col`` of what does not parse.
    """
    path = Path(file)
    try:
        stat = path.stat()
    except OSError as exc:
        raise ModelicaError(f"{path}: cannot read: {exc.strerror or exc}") from None
    return _parse_cached(str(path), stat.st_mtime_ns, stat.st_size)


def parse_text(text: str, file: str | os.PathLike = "<text>") -> SourceFile:
    """The classes of the Modelica ``text`` (``file`` names it in errors)."""
    return _parse_source(Source(Path(file), text))


def find_class(parsed: SourceFile, name: str) -> ClassDef | None:
    """The class ``name`` (full name) among the classes of ``parsed`` and their nested classes."""
    prefix = f"{parsed.within}." if parsed.within else ""
    if not name.startswith(prefix):
        return None
    parts = name[len(prefix):].split(".")
    cls = parsed.classes.get(parts[0])
    for part in parts[1:]:
        if cls is None:
            return None
        cls = cls.classes.get(part)
    return cls
