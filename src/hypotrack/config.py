"""Pipeline configuration: load, validate against JSON schemas, and fill defaults.

The configuration is a mapping of *sections* (``ssa``, ``generation_time``, ``sht``, …),
one per experiment, plus the top-level keys ``results`` and ``seed``. Each section is
validated against its own schema file ``<schema_dir>/<section>.schema.yaml``; a wrong value
raises :class:`ConfigError` naming the field path (``ssa.p_D``) and what was allowed. Beyond the
schemas: ``n_shards`` may not exceed ``n_runs`` wherever a section (or a sub-object) has both, and
a string where a schema expects an integer, number or boolean is first read as YAML (nested
``--config`` values arrive as strings).

A schema marks a mapping of tracker specifications (name → ``{kind: ..., options}``) with
``x-tracker-specs: true`` (or a mapping naming the experiment's own ``local_kinds`` and
``local_options``, which the schema checks itself); :func:`validate_config` hands each of them to
``tracker_specs`` (the pipeline passes :meth:`hypotrack.registry.TrackerSpec.from_config`, which knows every registered
kind's options), so a misspelled tracker option stops the run before any job starts.
"""

from __future__ import annotations

import re
from pathlib import Path

import jsonschema
import yaml

__all__ = ["ConfigError", "load_schema", "validate_config", "load_config"]


class ConfigError(ValueError):
    """A configuration value is outside its allowed range or of the wrong type."""


#: libyaml's safe loader where PyYAML was built with it (the same documents, ~10x faster): every Snakemake
#: invocation, each cluster job's included, reads the ~20 schemas.
_SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def load_schema(path) -> dict:
    with open(path) as fh:
        return yaml.load(fh, Loader=_SAFE_LOADER)


def _fill_defaults(instance: dict, schema: dict) -> None:
    for key, sub in schema.get("properties", {}).items():
        if "default" in sub and key not in instance:
            instance[key] = sub["default"]
        if isinstance(instance.get(key), dict) and sub.get("type") == "object":
            _fill_defaults(instance[key], sub)


_SCALAR_TYPES = {
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "boolean": lambda v: isinstance(v, bool),
    "null": lambda v: v is None,
}


_FLOAT = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def _resolve(schema, root):
    """``schema`` with a local ``$ref`` (``#/$defs/name``) followed."""
    while isinstance(schema, dict) and isinstance(schema.get("$ref"), str) and schema["$ref"].startswith("#/"):
        target = root
        for part in schema["$ref"][2:].split("/"):
            target = target.get(part, {}) if isinstance(target, dict) else {}
        schema = target
    return schema if isinstance(schema, dict) else {}


def _coerce_strings(instance, schema, root=None):
    """``instance`` with each string the schema types as integer, number, boolean (or null) replaced by
    its YAML value when that value has the type: ``snakemake --config 'ssa={n_runs: 3}'`` passes nested
    values as strings (``'3'``). A string that does not parse to the type is left for the validator
    to refuse with its usual message; a string the schema allows (``type: string``, ``enum``) stays."""
    root = schema if root is None else root
    schema = _resolve(schema, root)
    if isinstance(instance, str):
        types = schema.get("type")
        types = [types] if isinstance(types, str) else list(types or [])
        wanted = [t for t in types if t in _SCALAR_TYPES]
        if not wanted or "string" in types:
            return instance
        try:
            value = yaml.safe_load(instance)
        except yaml.YAMLError:
            return instance
        if isinstance(value, str) and "number" in wanted and _FLOAT.match(instance.strip()):
            value = float(instance)  # YAML 1.1 reads '1e-9' (no dot) as a string
        return value if any(_SCALAR_TYPES[t](value) for t in wanted) else instance
    if isinstance(instance, dict):
        props = schema.get("properties", {})
        extra = schema.get("additionalProperties")
        for key, value in instance.items():
            sub = props.get(key, extra if isinstance(extra, dict) else None)
            if sub is not None:
                instance[key] = _coerce_strings(value, sub, root)
        return instance
    if isinstance(instance, list) and isinstance(schema.get("items"), dict):
        for i, value in enumerate(instance):
            instance[i] = _coerce_strings(value, schema["items"], root)
    return instance


def _validate(instance, schema, prefix: str) -> None:
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(instance), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        field = ".".join([prefix, *map(str, e.absolute_path)]) if prefix else ".".join(map(str, e.absolute_path))
        raise ConfigError(f"invalid config value at '{field or '<root>'}': {e.message}")


def _check_shards(instance, prefix: str) -> None:
    """Every object holding both ``n_runs`` and ``n_shards`` needs ``n_shards <= n_runs`` (a shard
    without a run fails inside its job); JSON Schema cannot compare two fields."""
    if isinstance(instance, dict):
        runs, shards = instance.get("n_runs"), instance.get("n_shards")
        if isinstance(runs, int) and isinstance(shards, int) and shards > runs:
            raise ConfigError(f"invalid config value at '{prefix}.n_shards': n_shards must be at most n_runs "
                              f"(each shard runs at least one Monte Carlo run), got n_shards = {shards} > "
                              f"n_runs = {runs}")
        for key, value in instance.items():
            _check_shards(value, f"{prefix}.{key}")


def _tracker_specs(value, schema: dict, path: list):
    """``(path, mapping)`` of every mapping of tracker specifications the schema marks in ``value``."""
    if not isinstance(schema, dict):
        return
    marker = schema.get("x-tracker-specs")
    if marker:
        if isinstance(value, dict):
            yield path, value, marker if isinstance(marker, dict) else {}
        return
    if isinstance(value, dict):
        extra = schema.get("additionalProperties")
        for key, sub_value in value.items():
            sub = schema.get("properties", {}).get(key, extra if isinstance(extra, dict) else None)
            if sub is not None:
                yield from _tracker_specs(sub_value, sub, [*path, str(key)])


def validate_config(config: dict, schema_dir, *, tracker_specs=None) -> dict:
    """Validate ``config`` in place (filling schema defaults) and return it.

    Before validation, a string where the schema expects an integer, number or boolean is replaced
    by its YAML value if that has the type (nested ``--config`` values arrive as strings).

    ``schema_dir`` holds ``config.schema.yaml`` (top-level keys) and one
    ``<section>.schema.yaml`` per experiment section. ``tracker_specs(mapping, where)``, when given,
    checks each tracker specification the schemas mark (module docstring) and raises ``ValueError``
    naming the field.
    """
    schema_dir = Path(schema_dir)
    top = load_schema(schema_dir / "config.schema.yaml")
    _coerce_strings(config, top)
    _fill_defaults(config, top)
    _validate(config, top, "")
    for section, value in config.items():
        path = schema_dir / f"{section}.schema.yaml"
        if path.exists():
            schema = load_schema(path)
            value = config[section] = _coerce_strings(value, schema)
            _fill_defaults(value, schema)
            _validate(value, schema, section)
            for path, specs, marker in _tracker_specs(value, schema, [section]) if tracker_specs is not None else ():
                local = set(marker.get("local_options", ()))
                for name, spec in specs.items():
                    if not isinstance(spec, dict) or spec.get("kind") in marker.get("local_kinds", ()):
                        continue  # an experiment's own kind (a peer, a control), checked by its schema
                    try:
                        tracker_specs({k: v for k, v in spec.items() if k not in local}, ".".join([*path, str(name)]))
                    except ValueError as err:
                        raise ConfigError(str(err)) from None
            _check_shards(value, section)
        elif isinstance(value, dict):
            raise ConfigError(f"config section '{section}' has no schema ({path.name} missing)")
    return config


def load_config(path, schema_dir, *, tracker_specs=None) -> dict:
    """Read a YAML config file and validate it (:func:`validate_config`)."""
    with open(path) as fh:
        config = yaml.load(fh, Loader=_SAFE_LOADER) or {}
    return validate_config(config, schema_dir, tracker_specs=tracker_specs)
