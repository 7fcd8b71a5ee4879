"""The package's wire types and services against docs/wire-layout.json,
which `vref wire-layout --json` prints from the Rust types (a Rust test
keeps the file equal to that output). A Rust change not made here fails."""

from __future__ import annotations

import ctypes
import json
import os
from pathlib import Path
from typing import Any

import pytest

from vref_client import IpcSettings, services, wire

LAYOUT = Path(
    os.environ.get(
        "VREF_WIRE_LAYOUT", Path(__file__).resolve().parents[3] / "docs" / "wire-layout.json"
    )
)
FIX = "align clients/python/src/vref_client/wire.py (and services.py) with docs/wire-layout.json"


def records(kind: str) -> list[dict[str, Any]]:
    lines = [json.loads(line) for line in LAYOUT.read_text().splitlines() if line.strip()]
    return [r for r in lines if r["record"] == kind]


def ctype_name(t: Any) -> str:
    """A ctypes field type as the layout names it."""
    if isinstance(t, type) and issubclass(t, ctypes.Array):
        return f"[{ctype_name(t._type_)}; {t._length_}]"
    if isinstance(t, type) and issubclass(t, ctypes.Structure):
        return t.__name__
    names = {
        ctypes.c_uint8: "u8",
        ctypes.c_uint32: "u32",
        ctypes.c_uint64: "u64",
        ctypes.c_float: "f32",
    }
    if t in names:
        return names[t]
    raise AssertionError(f"unexpected ctypes field type {t}")


def test_the_schema_and_constants_are_the_rust_ones() -> None:
    (schema,) = records("schema")
    assert schema["schema_version"] == wire.SCHEMA_VERSION, FIX
    assert schema["constants"] == wire.CONSTANTS, FIX
    assert schema["iceoryx2"] == "0.10.0"
    import importlib.metadata

    assert importlib.metadata.version("iceoryx2") == schema["iceoryx2"]


@pytest.mark.parametrize("record", records("type"), ids=lambda r: r["name"])
def test_each_wire_type_matches(record: dict[str, Any]) -> None:
    t = wire.WIRE_TYPES.get(record["name"])
    assert t is not None, f"{record['name']} missing from vref_client.wire: {FIX}"
    assert wire.type_name_of(t) == record["type_name"], FIX
    assert (ctypes.sizeof(t), ctypes.alignment(t)) == (record["size"], record["align"]), FIX
    fields = [
        {
            "name": name,
            "offset": getattr(t, name).offset,
            "size": getattr(t, name).size,
            "type": ctype_name(ftype),
        }
        for name, ftype, *_ in t._fields_
    ]
    assert fields == record["fields"], FIX


def test_no_python_type_is_unknown_to_rust() -> None:
    assert set(wire.WIRE_TYPES) == {r["name"] for r in records("type")}


def test_the_numpy_views_match_the_layout() -> None:
    by_name = {r["name"]: r for r in records("type")}
    for dtype, name in (
        (wire.OBJECT_ENTRY_DTYPE, "ObjectEntry"),
        (wire.DECISION_ENTRY_DTYPE, "DecisionEntry"),
    ):
        layout = by_name[name]
        assert dtype.itemsize == layout["size"], name
        offsets = {f["name"]: (f["offset"], f["size"]) for f in layout["fields"]}
        for field in dtype.names or ():
            described = dtype.fields[field]  # type: ignore[index]
            sub, offset = described[0], described[1]
            assert (offset, sub.itemsize) == offsets[field], f"{name}.{field}"


def test_codes_match() -> None:
    rust = {r["name"]: {c["name"]: c["value"] for c in r["values"]} for r in records("codes")}
    assert rust == wire.CODES, FIX


def test_services_are_opened_as_the_rust_side_creates_them() -> None:
    (schema,) = records("schema")
    settings = IpcSettings(
        namespace=schema["namespace"],
        max_clients=schema["max_clients"],
        max_subscribers=schema["max_subscribers"],
        initial_objects=schema["initial_objects"],
    )
    rust = {}
    for r in records("service"):
        r = {k: v for k, v in r.items() if k not in ("record", "notifier", "listener")}
        rust[r["role"]] = r
    python = {s["role"]: s for s in services.catalogue(settings)}
    assert python.keys() == rust.keys(), FIX
    for role, spec in rust.items():
        assert python[role] == spec, f"{role}: {FIX}"
