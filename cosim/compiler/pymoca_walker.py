"""A faster drop-in for pymoca's tree walk (``TreeWalker.walk``), the same visits in the same order.

pymoca walks its trees (flattening: every equation twice, every symbol once; the CasADi
generator: the whole flat model) with a generic recursion that, for every node, builds the
names ``"enter" + class name`` and ``"exit" + class name``, looks them up with ``hasattr`` and
``getattr``, calls the listener's no-op methods, and asks ``skip_child`` for every attribute of
the node. That bookkeeping, not the listeners' work, was a third of flattening a generated
1000-state model.

This walk does the same per node class once per walk: it resolves the listener's enter and exit
methods (leaving out the base class's no-ops, ``pass`` in pymoca's ``TreeListener``), and the
children that ``skip_child`` would skip. Everything else is as pymoca does it: enterEvery,
enter<Class>, the children in ``order_keys`` order (looked up when visited, so a listener that
replaces a later child is seen), exitEvery, exit<Class>; dicts by their keys, lists by index.
It knows the skip rules of pymoca's ``TreeWalker`` and of the CasADi backend's
``GeneratorWalker`` (annotations skipped, symbols first); any other walker class keeps pymoca's
own walk.
"""
from __future__ import annotations


def install() -> None:
    """Replace ``TreeWalker.walk`` (idempotent; the original stays the fallback)."""
    from pymoca import ast
    from pymoca.backends.casadi.generator import GeneratorWalker
    from pymoca.tree import _listener

    walker_class = _listener.TreeWalker
    if getattr(walker_class.walk, "_cosim_fast", False):
        return
    original = walker_class.walk
    base = _listener.TreeListener
    no_ops = {name for name, f in vars(base).items()
              if name.startswith(("enter", "exit")) and name not in ("enterEvery", "exitEvery")
              and getattr(f, "__code__", None) is not None and f.__code__.co_code == _pass.__code__.co_code}
    parent_links = (ast.Class, ast.Symbol)
    argument = ast.ClassModificationArgument
    node_class = ast.Node
    skip_cache: dict[tuple[type, bool], frozenset] = {}

    def skipped(cls: type, generator: bool) -> frozenset:
        """The children of a ``cls`` node that TreeWalker (or GeneratorWalker) skips (cached)."""
        if (cls, generator) in skip_cache:
            return skip_cache[cls, generator]
        names = set()
        if issubclass(cls, parent_links):
            names |= {"parent", "parent_instance"}
        if issubclass(cls, argument):
            names |= {"scope", "__deepcopy__"}
        if generator and issubclass(cls, ast.Class):
            names.add("annotation")
        result = skip_cache[cls, generator] = frozenset(names)
        return result

    def method(listener, name: str):
        """The bound listener method ``name``, or None if it has none or only the base's no-op."""
        if not hasattr(listener, name):
            return None
        if name in no_ops and name not in vars(listener) \
                and getattr(type(listener), name, None) is getattr(base, name):
            return None
        return getattr(listener, name)

    def walk(self, listener, tree) -> None:
        kind = type(self)
        if kind is walker_class:
            generator = False
        elif kind is GeneratorWalker:
            generator = True
        else:  # a walker with rules of its own
            return original(self, listener, tree)

        every_enter = method(listener, "enterEvery")
        every_exit = method(listener, "exitEvery")
        # TreeListener's own enterEvery/exitEvery only keep the context: done inline below
        plain_every = all(name not in vars(listener) and getattr(type(listener), name, None) is getattr(base, name)
                          for name in ("enterEvery", "exitEvery"))
        context = listener.context if plain_every else None
        table: dict[type, tuple] = {}

        def entry(cls: type) -> tuple:
            name = cls.__name__
            found = table[cls] = (method(listener, "enter" + name), method(listener, "exit" + name),
                                  skipped(cls, generator))
            return found

        def visit(node) -> None:
            cls = node.__class__
            enter, exit_, skip = table.get(cls) or entry(cls)
            if plain_every:
                context[type(node).__name__] = node
            elif every_enter is not None:
                every_enter(node)
            if enter is not None:
                enter(node)
            attributes = node.__dict__
            keys = sorted(attributes.keys(), key=_symbols_first) if generator else attributes.keys()
            for child_name in keys:
                if child_name in skip:
                    continue
                child = attributes[child_name]
                if isinstance(child, node_class):  # (visit_any inlined: the hot path)
                    visit(child)
                elif isinstance(child, (dict, list)):
                    visit_container(child)
            if plain_every:
                context[type(node).__name__] = None
            elif every_exit is not None:
                every_exit(node)
            if exit_ is not None:
                exit_(node)

        def visit_container(container) -> None:
            if isinstance(container, dict):
                for k in container.keys():
                    visit_any(container[k])
            else:
                for i in range(len(container)):
                    visit_any(container[i])

        def visit_any(child) -> None:
            if isinstance(child, node_class):
                visit(child)
            elif isinstance(child, (dict, list)):
                visit_container(child)

        visit(tree)

    walk._cosim_fast = True
    walk.original = original  # pymoca's own walk (the tests compare the two)
    walker_class.walk = walk


def _pass(self, tree):
    pass


def _symbols_first(attribute: str) -> int:
    """GeneratorWalker's order: symbols before everything else (a stable sort)."""
    return 0 if attribute == "symbols" else 1
