"""Pipeline configuration: load, validate against JSON schemas, and fill defaults.

The configuration is a mapping of *sections* (``ssa``, ``generation_time``, ``sht``, …),
one per experiment, plus the top-level keys ``results`` and ``seed``. Each section is
validated against its own schema file ``<schema_dir>/<section>.schema.yaml``; a wrong value
raises :class:`ConfigError` naming the field path (``ssa.p_D``) and what was allowed.
"""

from __future__ import annotations

from pathlib import Path

import jsonschema
import yaml

__all__ = ["ConfigError", "load_schema", "validate_config", "load_config"]


class ConfigError(ValueError):
    """A configuration value is outside its allowed range or of the wrong type."""


def load_schema(path) -> dict:
    with open(path) as fh:
        return yaml.safe_load(fh)


def _fill_defaults(instance: dict, schema: dict) -> None:
    for key, sub in schema.get("properties", {}).items():
        if "default" in sub and key not in instance:
            instance[key] = sub["default"]
        if isinstance(instance.get(key), dict) and sub.get("type") == "object":
            _fill_defaults(instance[key], sub)


def _validate(instance, schema, prefix: str) -> None:
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(instance), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        field = ".".join([prefix, *map(str, e.absolute_path)]) if prefix else ".".join(map(str, e.absolute_path))
        raise ConfigError(f"invalid config value at '{field or '<root>'}': {e.message}")


def validate_config(config: dict, schema_dir) -> dict:
    """Validate ``config`` in place (filling schema defaults) and return it.

    ``schema_dir`` holds ``config.schema.yaml`` (top-level keys) and one
    ``<section>.schema.yaml`` per experiment section.
    """
    schema_dir = Path(schema_dir)
    top = load_schema(schema_dir / "config.schema.yaml")
    _fill_defaults(config, top)
    _validate(config, top, "")
    for section, value in config.items():
        path = schema_dir / f"{section}.schema.yaml"
        if path.exists():
            schema = load_schema(path)
            _fill_defaults(value, schema)
            _validate(value, schema, section)
        elif isinstance(value, dict):
            raise ConfigError(f"config section '{section}' has no schema ({path.name} missing)")
    return config


def load_config(path, schema_dir) -> dict:
    """Read a YAML config file and validate it."""
    with open(path) as fh:
        config = yaml.safe_load(fh) or {}
    return validate_config(config, schema_dir)
