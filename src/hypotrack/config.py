"""Pipeline configuration: load, validate against JSON schemas, and fill defaults.

The configuration is a mapping of *sections* (``ssa``, ``generation_time``, ``sht``, …),
one per experiment, plus the top-level keys ``results`` and ``seed``. Each section is
validated against its own schema file ``<schema_dir>/<section>.schema.yaml``; a wrong value
raises :class:`ConfigError` naming the field path (``ssa.p_D``) and what was allowed.

A schema marks a mapping of tracker specifications (name → ``{kind: ..., options}``) with
``x-tracker-specs: true`` (or a mapping naming the experiment's own ``local_kinds`` and
``local_options``, which the schema checks itself); :func:`validate_config` hands each of them to ``tracker_specs`` (the
pipeline passes :meth:`hypotrack.registry.TrackerSpec.from_config`, which knows every registered
kind's options), so a misspelled tracker option stops the run before any job starts.
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

    ``schema_dir`` holds ``config.schema.yaml`` (top-level keys) and one
    ``<section>.schema.yaml`` per experiment section. ``tracker_specs(mapping, where)``, when given,
    checks each tracker specification the schemas mark (module docstring) and raises ``ValueError``
    naming the field.
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
            for path, specs, marker in _tracker_specs(value, schema, [section]) if tracker_specs is not None else ():
                local = set(marker.get("local_options", ()))
                for name, spec in specs.items():
                    if not isinstance(spec, dict) or spec.get("kind") in marker.get("local_kinds", ()):
                        continue  # an experiment's own kind (a peer, a control), checked by its schema
                    try:
                        tracker_specs({k: v for k, v in spec.items() if k not in local}, ".".join([*path, str(name)]))
                    except ValueError as err:
                        raise ConfigError(str(err)) from None
        elif isinstance(value, dict):
            raise ConfigError(f"config section '{section}' has no schema ({path.name} missing)")
    return config


def load_config(path, schema_dir, *, tracker_specs=None) -> dict:
    """Read a YAML config file and validate it (:func:`validate_config`)."""
    with open(path) as fh:
        config = yaml.safe_load(fh) or {}
    return validate_config(config, schema_dir, tracker_specs=tracker_specs)
