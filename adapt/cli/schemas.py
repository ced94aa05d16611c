"""``adapt schemas list`` and ``adapt plugins list``: what is registered, and where it came from.

``adapt schemas list [--plugins M ...] [--json]``
    every schema type with its kind, ports, parameters and origin (``built-in``, or the
    plugin that registered it).
``adapt plugins list [--plugins M ...] [--json]``
    the installed plugins (entry points) and those named, what each registered, and the
    reality kinds plugins added with their keys.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add ``schemas list``."""
    p = sub.add_parser("schemas", help="list the schema types",
                       description="Schema types: what each provides and consumes, and its "
                       "parameters.")
    ps = p.add_subparsers(dest="schemas_command", metavar="SUBCOMMAND")
    ps.required = True
    lst = ps.add_parser("list", help="list the registered schema types")
    _plugins(lst)
    lst.add_argument("--json", action="store_true", help="print the types as JSON")
    lst.set_defaults(func=_list)

    p = sub.add_parser("plugins", help="list the plugins and what they registered",
                       description="Plugins: the installed ones (entry points adapt.schemas and "
                       "adapt.realities) and those named, with what each registered.")
    pp = p.add_subparsers(dest="plugins_command", metavar="SUBCOMMAND")
    pp.required = True
    pl = pp.add_parser("list", help="list the plugins, and the reality kinds they added")
    _plugins(pl)
    pl.add_argument("--json", action="store_true", help="print the plugins as JSON")
    pl.set_defaults(func=_list_plugins)


def _plugins(p: Any) -> None:
    p.add_argument("--plugins", nargs="+", default=[], metavar="MODULE",
                   help="also load these plugins (module names or .py files), as a scenario's "
                   "plugins: key does")


def _load(args: argparse.Namespace) -> None:
    from adapt.plugins import load_installed, load_plugin

    load_installed()
    for name in args.plugins:
        load_plugin(name)


def _list(args: argparse.Namespace) -> int:
    from adapt.schemas import REGISTRY

    _load(args)
    if args.json:
        print(json.dumps([{**spec.as_json(), "origin": REGISTRY.origin(spec.name)}
                          for spec in REGISTRY]))
        return 0
    for spec in REGISTRY:
        single = ", one at a time" if spec.singleton else ""
        print(f"{spec.name} ({spec.kind.value}{single}; {REGISTRY.origin(spec.name)})")
        print(f"  {spec.doc}")
        for label, ports in (("provides", spec.provides), ("consumes", spec.consumes)):
            for port in ports:
                print(f"  {label} {port.name}: {port.doc}")
        for param in spec.parameters:
            print(f"  - {param.describe()}")
        print()
    return 0


def _list_plugins(args: argparse.Namespace) -> int:
    from adapt.plugins import loaded_plugins
    from adapt.scenario import REALITIES

    _load(args)
    plugins = loaded_plugins()
    if args.json:
        print(json.dumps({"plugins": [p.as_json() for p in plugins],
                          "realities": [{**r.as_json(), "origin": REALITIES.origin(r.name)}
                                        for r in REALITIES]}))
        return 0
    for p in plugins:
        print(f"{p.name} ({p.found.value}): module {p.module}"
              + (f", {p.file}" if p.file else ""))
        print("  registered: " + (", ".join(p.registered) or "nothing"))
    if not plugins:
        print("no plugins (install one with an adapt.schemas or adapt.realities entry point, or "
              "name one with --plugins or a scenario's plugins: key)")
    for r in REALITIES:
        print(f"reality kind {r.name} ({REALITIES.origin(r.name)}): {r.doc}")
        for param in r.parameters:
            print(f"  - {param.describe()}")
    return 0
