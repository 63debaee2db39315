"""Pipeline configuration: every shipped config validates; a bad value names its field."""

from pathlib import Path

import pytest
import yaml

from hypotrack.config import ConfigError, load_config, validate_config

ROOT = Path(__file__).resolve().parents[2]
SCHEMAS = ROOT / "workflows" / "config" / "schema"


def _merged(*names):
    config = {}
    for name in names:
        with open(ROOT / "workflows" / "config" / name) as fh:
            for key, value in (yaml.safe_load(fh) or {}).items():
                if isinstance(value, dict) and isinstance(config.get(key), dict):
                    config[key] = {**config[key], **value}
                else:
                    config[key] = value
    return config


def test_default_config_validates():
    config = load_config(ROOT / "workflows" / "config" / "default.yaml", SCHEMAS)
    assert config["results"] == "results"


def test_quick_config_validates_over_default():
    validate_config(_merged("default.yaml", "quick.yaml"), SCHEMAS)


def test_every_section_has_a_schema():
    config = _merged("default.yaml", "quick.yaml")
    sections = {k for k, v in config.items() if isinstance(v, dict)}
    schemas = {p.name.removesuffix(".schema.yaml") for p in SCHEMAS.glob("*.schema.yaml")} - {"config"}
    assert sections == schemas


def test_bad_top_level_value_names_field():
    with pytest.raises(ConfigError, match="seed"):
        validate_config({"results": "results", "seed": -3}, SCHEMAS)


def test_section_without_schema_is_refused():
    with pytest.raises(ConfigError, match="no_such_experiment"):
        validate_config({"results": "results", "seed": 1, "no_such_experiment": {"a": 1}}, SCHEMAS)


def test_every_section_rejects_an_unknown_key():
    config = _merged("default.yaml")
    for section, value in config.items():
        if not isinstance(value, dict):
            continue
        bad = {**config, section: {**value, "not_a_parameter": 1}}
        with pytest.raises(ConfigError, match=section):
            validate_config(bad, SCHEMAS)
