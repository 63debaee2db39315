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


@pytest.mark.parametrize("section, path", [("cardinality", ()), ("closely_spaced", ()), ("glmb_benchmark", ()),
                                           ("swaps", ()), ("sht", ()), ("sht", ("sweep",)), ("williams2015", ())])
def test_more_shards_than_runs_is_refused_at_validation(section, path):
    """It passed validation and failed inside the job; every section with both fields is checked."""
    config = _merged("default.yaml")
    obj = config[section]
    for key in path:
        obj = obj[key]
    obj["n_shards"] = obj["n_runs"] + 1
    field = ".".join([section, *path, "n_shards"])
    with pytest.raises(ConfigError, match=rf"^invalid config value at '{field}': n_shards must be at most n_runs"):
        validate_config(config, SCHEMAS)


def test_every_section_with_runs_and_shards_is_covered():
    """The test above lists every object of the default config that has both fields."""
    found = []

    def walk(obj, path):
        if isinstance(obj, dict):
            if "n_runs" in obj and "n_shards" in obj:
                found.append(path)
            for k, v in obj.items():
                walk(v, (*path, k))

    walk(_merged("default.yaml", "quick.yaml"), ())
    assert sorted(found) == sorted([("cardinality",), ("closely_spaced",), ("glmb_benchmark",), ("swaps",),
                                    ("sht",), ("sht", "sweep"), ("williams2015",)])


def test_nested_config_strings_are_read_as_the_schema_types():
    """``snakemake --config 'ssa={n_runs: 3}'`` passes nested values as strings ('3')."""
    config = _merged("default.yaml")
    config["swaps"].update(n_runs="30", n_shards="3", sigma="5e-1")  # YAML 1.1 reads '5e-1' as a string
    config["seed"] = "7"
    validate_config(config, SCHEMAS)
    assert (config["swaps"]["n_runs"], config["swaps"]["n_shards"], config["swaps"]["sigma"]) == (30, 3, 0.5)
    assert config["seed"] == 7 and config["results"] == "results"


@pytest.mark.parametrize("value", ["three", "3.5", "true", ""])
def test_a_string_that_is_not_the_type_keeps_the_original_error(value):
    config = _merged("default.yaml")
    config["swaps"]["n_runs"] = value
    with pytest.raises(ConfigError, match=rf"invalid config value at 'swaps.n_runs': '{value}' is not of type 'integer'"):
        validate_config(config, SCHEMAS)


def test_a_string_field_keeps_its_string():
    config = _merged("default.yaml")
    config["results"] = "123"
    validate_config(config, SCHEMAS)
    assert config["results"] == "123"


def test_snakemakes_own_parsing_of_a_nested_config_validates():
    """``snakemake --config 'swaps={n_runs: 30, n_shards: 3}'``: Snakemake reads the nested mapping with
    YAML's base loader, every value a string; the schema's types are restored before validation."""
    cli = pytest.importorskip("snakemake.cli")
    given = cli.parse_config(["swaps={n_runs: 30, n_shards: 3}"])
    assert given == {"swaps": {"n_runs": "30", "n_shards": "3"}}
    config = _merged("default.yaml")
    config["swaps"].update(given["swaps"])
    validate_config(config, SCHEMAS)
    assert (config["swaps"]["n_runs"], config["swaps"]["n_shards"]) == (30, 3)
