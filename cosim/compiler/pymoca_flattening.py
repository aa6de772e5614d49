"""pymoca's ``_flatten_instance`` (pymoca/tree/_flattening.py of pymoca 0.12.0) with two changes.

This one function is vendored from pymoca under its BSD licence (below) and installed in its place
by :func:`cosim.compiler.pymoca_patches.apply`. Everything else it calls is looked up in pymoca's
module when called (``_flattening._resolve_name`` ...), so cosim's other patches of those
functions apply here as they do in pymoca's own code. The changes, each marked ``# cosim``:

- The symbols a component added to the flat class were found as the set difference of all its
  symbols before and after the component: quadratic in the size of the model (a 3000-state chain
  spent 60 % of its flattening there). They are the entries added last (:func:`added_keys`).
- The flat symbol of an array component of a derived type (``Length p[3]`` with
  ``type Length = Real(...)``, the type's ``Real`` under the component's own name) kept the type's
  scalar dimensions; it gets the component's dimensions (:func:`leaf_dimensions`). Report:
  docs/pymoca-upstream.md#derived-type-arrays.

The flat models are otherwise the same as pymoca's (and as the FMUs cosim built with the same
changes made by rewriting pymoca's source text before).

Copyright (c) 2016, James Goppert and the Pymoca contributors.
All rights reserved.

Redistribution and use in source and binary forms, with or without
modification, are permitted provided that the following conditions are met:

* Redistributions of source code must retain the above copyright notice, this
  list of conditions and the following disclaimer.

* Redistributions in binary form must reproduce the above copyright notice,
  this list of conditions and the following disclaimer in the documentation
  and/or other materials provided with the distribution.

* Neither the name of pymoca nor the names of its
  contributors may be used to endorse or promote products derived from
  this software without specific prior written permission.

THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS"
AND ANY EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE
IMPLIED WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDER OR CONTRIBUTORS BE LIABLE
FOR ANY DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL
DAMAGES (INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR
SERVICES; LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER
CAUSED AND ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY,
OR TORT (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE
OF THIS SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE.
"""
# pymoca is imported here at the top: this module is imported only when the patches are applied,
# before the first flattening (cosim --help and the other commands never load it).
from __future__ import annotations

import copy
import itertools
from typing import cast

from pymoca import ast
from pymoca.tree import LookupOptions, RecursionGuard
from pymoca.tree import _flattening
from pymoca.tree.instance import InstanceClass, InstanceSymbol, InstanceTree


def added_keys(symbols: dict, before: int) -> set:
    """The keys added to ``symbols`` since it had ``before`` entries: the last ones (a dict keeps
    insertion order, and the flattening only adds to the flat class's symbols)."""
    added = len(symbols) - before
    return set(itertools.islice(reversed(symbols), added)) if added > 0 else set()


def leaf_dimensions(symbol, outer_dims) -> None:
    """The dimensions of the built-in leaf of a component of a derived type (``Units.Length r[3]``,
    whose flat symbol is the type's ``Real`` under the component's name): the component's own,
    followed by the type's (``type V = Real[2]``)."""
    def sizes(dims):
        return [d for dl in dims or [] for d in dl if d is not None and getattr(d, "value", 0) is not None]

    outer = sizes(outer_dims)
    if outer:
        symbol.dimensions = [outer + sizes(symbol.dimensions)]


def flatten_instance(
    instance: InstanceClass,
    flat_class: InstanceClass,
    *,
    guard: RecursionGuard | None = None,
    opts: LookupOptions | None = None,
    prefix: str = "",
) -> None:
    """Flatten an instance class

    :param instance: The instance class to flatten
    :param flat_class: The flattened class; function calls discovered while flattening
        are accumulated directly into ``flat_class.functions``
    :param guard: Cycle detection state shared across a single operation
    :param opts: Name lookup options (instantiate_in_place, search flags, etc.)
    :param prefix: The prefix for the current instance
    :return: None

    The passed instance may be updated by fully instantiating elements as needed.
    We allow the top-level flattened instance to retain connectors so that we can
    flatten a set of components and connect them together later.
    """
    # Outline of spec 3.5 section 5.6.2 *Generation of the flat equation system*.
    # "Simple Type" below means Integer, Real, Boolean, String, enumeration, Clock,
    # or External Object.
    #
    # 1 Recursively walk the tree, beginning at the class to be flattened, and process
    # components with the following items used throughout:
    # * A. "all references by name in conditional declarations, modifications, dimension
    #   definitions, annotations, equations and algorithms are resolved to the real
    #   instance to which they are referring to ... [Either the referenced instance
    #   belongs to the model to be simulated the path starts at the model itself, or if
    #   not, it starts at the unnamed root of the instance tree, e.g. in case of a
    #   constant in a package.]"
    # * B. Names are replaced by the global unique identifier of the instance "[This
    #   identifier is normally constructed from the names of the instances along a path
    #   in the instance tree (and omitting the unnamed nodes of extends clauses),
    #   separated by dots. Either the referenced instance belongs to the model to be
    #   simulated the path starts at the model itself, or if not, it starts at the
    #   unnamed root of the instance tree, e.g. in case of a constant in a package.]"
    # * C. Classes and symbols are instantiated as needed (if not a fully instantiated instance)
    # * D. Classes are ignored unless needed by components
    # * E. Function calls encountered in the above are processed as needed:
    #   - Fill the call with default arguments (section 12.4.1) (TODO)
    #   - Look up the function in the instance tree
    #   - Recursively flatten the function call
    #   - Add to the list of functions
    #
    # 1.1 Insert components into the variables list
    # 1.2 Evaluate the conditional declaration expression and mark the declaration for
    #     deletion (TODO)
    # 1.3 Resolve dimensions, including enclosing instances
    # 1.4 Resolve modifications of value attributes of simple types and records (TODO: records)
    # 1.5 Resolve modifications of other attributes of simple types
    # 1.6 Recursively "handle" non-simple types
    # 1.7 Resolve references in equations and algorithms
    # 1.8 Recursively "handle" unnamed extends instances
    # 1.9 Check that all references now point to a valid instance (not conditionally false)
    #
    # 2 Generate connect equations for all connections in the flattened tree
    #
    # 3 Process transitions in the flattened tree (TODO)

    if guard is None:
        guard = RecursionGuard()
    if opts is None:
        opts = LookupOptions()

    # 1.1–1.6 Process local symbols per MLS 5.6.2
    for name, symbol in list(cast(dict[str, InstanceSymbol], instance.symbols).items()):

        assert isinstance(name, str)
        # Steps A-D
        if name in InstanceTree.BUILTIN_TYPES and prefix:
            flat_name = prefix
        elif prefix:
            flat_name = prefix + "." + name
        else:
            flat_name = name
        flat_symbol: InstanceSymbol = copy.copy(symbol)
        # dimensions inner lists are shared with the parsed AST via
        # _copy_symbol_contents; _resolve_dimensions mutates dim_list[i] in-place,
        # so make fresh inner lists to avoid corrupting the shared parsed AST.
        if flat_symbol.dimensions:
            flat_symbol.dimensions = [list(dl) for dl in flat_symbol.dimensions]
        # Strip input/output prefixes from nested symbols — these are
        # connector-local causality markers (MLS 9.1.1) and should not
        # propagate to the parent model's flattened namespace.
        if prefix:
            flat_symbol.prefixes = [p for p in flat_symbol.prefixes if p not in ("input", "output")]
        if symbol.type.name in InstanceTree.BUILTIN_TYPES:
            flat_symbol.name = flat_name
            flat_class.symbols[flat_name] = flat_symbol
        elif isinstance(flat_symbol.type, InstanceClass) and ast.is_enumeration(flat_symbol.type):
            # Enumeration-typed symbols are simple leaf types (MLS 4.8.5), treated
            # symmetrically with builtin types: place directly in the flat namespace.
            flat_symbol.name = flat_name
            flat_class.symbols[flat_name] = flat_symbol
        elif not isinstance(flat_symbol.type, InstanceClass):
            # scope==instance (declaring class) already differs from flat_class (root); no
            # derived-vs-base asymmetry here, so name_flat_class is not needed.
            resolved = _flattening._resolve_name(
                flat_symbol.type,
                instance,
                flat_class,
                guard=guard,
                opts=opts,
            )
            is_class = isinstance(resolved, InstanceClass)
            flat_symbol.type = resolved if is_class else resolved.parent  # type: ignore[assignment]
            # If the resolved type is an enumeration, add the symbol here now that
            # the type is known (covers the ComponentRef → InstanceClass resolution path).
            if ast.is_enumeration(flat_symbol.type) and flat_name not in flat_class.symbols:
                flat_symbol.name = flat_name
                flat_class.symbols[flat_name] = flat_symbol

        # 1.2 Evaluate conditional declarations (TODO)
        _flattening._evaluate_conditional_declarations(flat_symbol, flat_class)

        # 1.3 Resolve dimensions, including enclosing instances
        _flattening._resolve_dimensions(
            flat_symbol,
            instance,
            flat_class,
            guard=guard,
            opts=opts,
        )

        # 1.4 Resolve modifications of value attributes of simple types and records
        # 1.5 Resolve modifications of other attributes of simple types
        if (
            flat_symbol.type.name in InstanceTree.BUILTIN_TYPES
            or ast.is_enumeration(flat_symbol.type)
            or "record" in flat_symbol.prefixes
        ):
            _flattening._resolve_modifications(
                flat_symbol,
                flat_class,
                guard=guard,
                opts=opts,
            )
        else:
            # 1.6 Recursively "handle" non-simple types
            symbols_before_recursive = len(flat_class.symbols)  # cosim: a count, not a set
            assert isinstance(flat_symbol.type, InstanceClass)
            _flattening._flatten_instance(
                flat_symbol.type,
                flat_class,
                guard=guard,
                opts=opts,
                prefix=flat_name,
            )

            # Propagate outer symbol dimensions to inner symbols (MLS 5.6.2 step 1.3)
            # Always propagate (including scalar [[None]]) to preserve nesting depth
            # for backend indexing.  Only propagate to symbols added by this recursive
            # call to avoid double-prepending when extends chains share component names.
            outer_dims = flat_symbol.dimensions
            flat_name_prefix = flat_name + "."
            new_sym_names = added_keys(flat_class.symbols, symbols_before_recursive)  # cosim
            outer_variability = next(
                (p for p in _flattening._VARIABILITY_ORDER if p in flat_symbol.prefixes), None
            )
            for sym_name in new_sym_names:
                if sym_name == flat_name:  # cosim: the leaf of a derived type
                    leaf_dimensions(flat_class.symbols[sym_name], outer_dims)
                if sym_name.startswith(flat_name_prefix):
                    sym = flat_class.symbols[sym_name]
                    sym.dimensions = outer_dims + sym.dimensions
                    # Propagate outer variability to structured-component elements;
                    # the most restrictive variability wins (MLS 4.4.4.1).
                    if outer_variability is not None:
                        _flattening._apply_outer_variability(sym, outer_variability)

            # Propagate outer symbol prefixes and replaceable to the leaf builtin symbol
            inner_sym = flat_class.symbols.get(flat_name)
            if inner_sym is not None and flat_name in new_sym_names:
                for pfx in flat_symbol.prefixes:
                    if pfx not in ("input", "output") and pfx not in inner_sym.prefixes:
                        inner_sym.prefixes.insert(0, pfx)
                inner_sym.replaceable = flat_symbol.replaceable
                inner_sym.final = flat_symbol.final
                inner_sym.inner = flat_symbol.inner
                inner_sym.outer = flat_symbol.outer

    # 1.8 Recursively "handle" unnamed extends instances.
    # Extends must be processed before equations (step 1.7) so that inherited symbols
    # are present when equations of the current class are resolved.
    for extends in instance.extends:  # type: ignore[attr-defined]
        if not isinstance(extends, InstanceClass):
            continue
        _flattening._flatten_instance(
            extends,
            flat_class,
            guard=guard,
            opts=opts,
            prefix=prefix,
        )

    # 1.7 Resolve references in equations and algorithms
    _flattening._collect_and_resolve_equations(instance, flat_class, prefix)

    # Steps 1.9, 2, and 3 are done outside the recursion in the caller
