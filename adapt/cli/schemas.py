"""``adapt schemas list``: the registered schema types, their ports and parameters."""

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
    lst.add_argument("--json", action="store_true", help="print the types as JSON")
    lst.set_defaults(func=_list)


def _list(args: argparse.Namespace) -> int:
    from adapt.schemas import REGISTRY

    if args.json:
        print(json.dumps([spec.as_json() for spec in REGISTRY]))
        return 0
    for spec in REGISTRY:
        single = ", one at a time" if spec.singleton else ""
        print(f"{spec.name} ({spec.kind.value}{single})")
        print(f"  {spec.doc}")
        for label, ports in (("provides", spec.provides), ("consumes", spec.consumes)):
            for port in ports:
                print(f"  {label} {port.name}: {port.doc}")
        for param in spec.parameters:
            print(f"  - {param.describe()}")
        print()
    return 0
