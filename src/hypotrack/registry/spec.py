"""Tracker specifications: a registered kind plus its options, validated against one schema.

The options of every kind, with their defaults, are stated once, in ``presets.yaml`` beside this
module (kinds registered at run time bring their own option schemas). :meth:`TrackerSpec.from_config`
validates a mapping ``{kind: ..., option: value, ...}`` against its kind's JSON schema — an unknown
kind or option, a wrong type or a value out of range is a :class:`SpecError` naming it — and fills
the defaults.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib.resources import files
from types import MappingProxyType

import jsonschema
import yaml

__all__ = ["BUILTIN", "FAMILIES", "SpecError", "TrackerSpec", "Preset", "option_schema", "register", "unregister", "preset",
           "kinds"]


class SpecError(ValueError):
    """A tracker specification names an unknown kind or option, or an option out of its range."""


def _load():
    with (files(__package__) / "presets.yaml").open(encoding="utf-8") as fh:
        return yaml.safe_load(fh)


#: ``presets.yaml``: the built-in kinds and the families' options, as read.
BUILTIN = _load()
#: The families' shared option schemas (``engine``, ``single``).
FAMILIES = MappingProxyType({name: MappingProxyType(f["options"]) for name, f in BUILTIN["families"].items()})


@dataclass(frozen=True)
class Preset:
    """A registered kind: how to build it and which options it takes.

    ``builder(problem, *, seed, **options)`` returns a tracker (:class:`hypotrack.protocol.Tracker`);
    ``options`` maps each of the kind's own option names to its JSON schema (with ``default``);
    ``family`` (``"engine"`` or ``"single"``) adds the family's shared options; ``defaults``
    overrides family defaults for this kind. ``no_fusion``, when not empty, says why the kind has no
    multi-sensor form although its family has one (:func:`hypotrack.registry.build` on a
    :class:`~.problem.MultiSensorProblem` refuses it with this reason).
    """

    kind: str
    builder: object
    family: str
    description: str = ""
    options: Mapping = field(default_factory=dict)
    defaults: Mapping = field(default_factory=dict)
    no_fusion: str = ""

    def __post_init__(self):
        if not isinstance(self.kind, str) or not self.kind.isidentifier():
            raise ValueError(f"kind must be an identifier, got {self.kind!r}")
        if self.family not in FAMILIES:
            raise ValueError(f"family must be one of {sorted(FAMILIES)}, got {self.family!r}")
        if not callable(self.builder):
            raise TypeError(f"builder must be callable, got {type(self.builder).__name__}")
        clash = sorted(set(self.options) & set(FAMILIES[self.family]))
        if clash:
            raise ValueError(f"options {clash} are already options of the {self.family} family")
        for name, schema in self.options.items():
            if not isinstance(schema, Mapping) or "default" not in schema:
                raise ValueError(f"option {name!r} of kind {self.kind!r} needs a schema with a default")
            jsonschema.Draft202012Validator.check_schema(dict(schema))
        unknown = sorted(set(self.defaults) - set(FAMILIES[self.family]))
        if unknown:
            raise ValueError(f"defaults {unknown} are not options of the {self.family} family")
        if not isinstance(self.no_fusion, str):
            raise TypeError(f"no_fusion must be a string (why the kind cannot fuse sensors; empty: it can), got "
                            f"{type(self.no_fusion).__name__}")

    def schema(self) -> dict:
        """The JSON schema of this kind's specification (``kind`` plus every option, defaults filled)."""
        props = {name: copy.deepcopy(dict(s)) for name, s in FAMILIES[self.family].items()}
        for name, value in self.defaults.items():
            props[name]["default"] = value
        props.update({name: copy.deepcopy(dict(s)) for name, s in self.options.items()})
        props["kind"] = {"const": self.kind}
        return {"type": "object", "required": ["kind"], "additionalProperties": False, "properties": props,
                "description": self.description}


def option_schema(p: Preset, name: str) -> dict:
    """The JSON schema of option ``name`` of preset ``p`` (its family's or its own)."""
    return p.schema()["properties"][name]


_PRESETS: dict[str, Preset] = {}


def register(kind: str, builder, *, family: str, description: str = "", options=None, defaults=None,
             replace: bool = False, no_fusion: str = "") -> Preset:
    """Register a tracker kind: ``builder(problem, *, seed, **options)`` returning a tracker.

    ``options`` maps the kind's own option names to JSON schemas, each with its ``default``; the
    ``family``'s shared options (``presets.yaml``) come with it. Every experiment and the Stone
    Soup adapter build their trackers through the registry, so a registered kind reaches all of
    them. An existing kind is refused unless ``replace``. A kind of the ``engine`` or ``single``
    family fuses several sensors (:class:`~.problem.MultiSensorProblem`) unless ``no_fusion`` says why not.
    """
    if kind in _PRESETS and not replace:
        raise ValueError(f"kind {kind!r} is already registered (pass replace=True to replace it)")
    p = Preset(kind, builder, family, description, MappingProxyType(dict(options or {})),
               MappingProxyType(dict(defaults or {})), no_fusion)
    _PRESETS[kind] = p
    return p


def unregister(kind: str) -> None:
    """Remove a registered kind (e.g. one a test registered)."""
    if kind not in _PRESETS:
        raise KeyError(f"kind {kind!r} is not registered")
    del _PRESETS[kind]


def preset(kind: str, where: str = "kind") -> Preset:
    """The registered :class:`Preset` of ``kind``; a :class:`SpecError` naming ``where`` otherwise."""
    try:
        return _PRESETS[kind]
    except (KeyError, TypeError):
        raise SpecError(f"invalid tracker option at '{where}': unknown tracker kind {kind!r} (registered: "
                        f"{', '.join(sorted(_PRESETS))})") from None


def kinds(family: str | None = None) -> tuple:
    """The registered kinds (of one family), in registration order."""
    return tuple(k for k, p in _PRESETS.items() if family is None or p.family == family)


def _fill(instance: dict, schema: dict) -> dict:
    """``instance`` with every absent option set to its default (nested objects too)."""
    out = dict(instance)
    for name, sub in schema.get("properties", {}).items():
        if name not in out and "default" in sub:
            out[name] = copy.deepcopy(sub["default"])
        if isinstance(out.get(name), Mapping) and "properties" in sub:
            out[name] = _fill(dict(out[name]), sub)
    return out


@dataclass(frozen=True)
class TrackerSpec:
    """One tracker: a registered ``kind`` and its ``options`` (every option, defaults filled).

    Build it from a config mapping with :meth:`from_config` (validated) and a tracker from it with
    :func:`hypotrack.registry.build`.

    Examples
    --------
    >>> from hypotrack.registry import TrackerSpec
    >>> spec = TrackerSpec.from_config({"kind": "rfisst", "n_steps": 500})
    >>> spec.options["n_steps"], spec.options["completion_rounds"], spec.options["max_hypotheses"]
    (500, 2, 100)
    >>> TrackerSpec.from_config({"kind": "rfisst", "n_step": 500})
    Traceback (most recent call last):
    ...
    hypotrack.registry.spec.SpecError: invalid tracker option at 'n_step': unknown option of kind 'rfisst' (its options: burn_in, cap, completion_rounds, factored, gate_probability, init, max_hypotheses, mcmc_variant, merge_duplicates, n_steps, population)
    """

    kind: str
    options: Mapping

    @classmethod
    def from_config(cls, mapping, where: str = "") -> "TrackerSpec":
        """Validate ``{kind: ..., option: value, ...}`` and fill its defaults; ``where`` (e.g.
        ``"ssa50.trackers.rfisst"``) prefixes the field in error messages."""
        prefix = f"{where}." if where else ""
        if isinstance(mapping, TrackerSpec):
            mapping = {"kind": mapping.kind, **mapping.options}
        if not isinstance(mapping, Mapping) or "kind" not in mapping:
            raise SpecError(f"invalid tracker at '{where or '<spec>'}': a mapping with a 'kind' is required, "
                            f"got {mapping!r}")
        p = preset(mapping["kind"], where=f"{prefix}kind")
        schema = p.schema()
        extra = sorted(set(mapping) - set(schema["properties"]))
        if extra:
            raise SpecError(f"invalid tracker option at '{prefix}{extra[0]}': unknown option of kind "
                            f"{p.kind!r} (its options: {', '.join(sorted(set(schema['properties']) - {'kind'}))})")
        errors = sorted(jsonschema.Draft202012Validator(schema).iter_errors(dict(mapping)),
                        key=lambda e: list(e.absolute_path))
        if errors:
            e = errors[0]
            path = ".".join(map(str, e.absolute_path)) or "<spec>"
            raise SpecError(f"invalid tracker option at '{prefix}{path}': {e.message}")
        filled = _fill(dict(mapping), schema)
        return cls(p.kind, MappingProxyType({k: v for k, v in filled.items() if k != "kind"}))

    def to_config(self) -> dict:
        """The specification as a plain mapping (``kind`` first), e.g. for a results table."""
        return {"kind": self.kind, **copy.deepcopy(dict(self.options))}
