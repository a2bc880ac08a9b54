"""The package's keywords are the library's option declarations
(stvd._core.option_declarations, the ones the tool parses and documents its
command lines with): each call takes the keywords declared for its command
and no undeclared option, their defaults are the declared ones, and the
values they accept and the messages they give come from the same checks,
in keyword names."""

import inspect
import math

import pytest

import stvd
import stvd.cohort
from conftest import CC_BODY, DIPY_5D

DECLARATIONS = stvd._core.option_declarations()

# The package's calls for each command; `stvd path` is a propagation, then
# its paths.
CALLS = {
    "distance": (stvd.distance, stvd.propagate),
    "path": (stvd.propagate, stvd.trace_paths),
    "connectivity": (stvd.connectivity,),
    "surface": (stvd.surface_distance,),
    "tet-mesh": (stvd.tet_mesh_distance,),
    "cohort": (stvd.cohort.run,),
}

# Parameters that are not options of the command line: the inputs and how
# the call runs; label_names names the regions of stvd.Connectivity (the
# tool's table has label values only).
NOT_OPTIONS = {"tensors", "affine", "progress", "result", "vertices", "faces", "points", "tetrahedra",
               "metric_values", "manifest", "outdir", "client", "scheduler", "workers", "host", "serial",
               "connectivity", "maps", "split_seed_sets", "threads", "report", "label_names"}


def parameters(call):
    return inspect.signature(call).parameters


@pytest.mark.parametrize("command", sorted(CALLS))
def test_each_call_takes_the_keywords_declared_for_its_command(command):
    taken = set().union(*(parameters(call) for call in CALLS[command]))
    declared = {d["keyword"] for d in DECLARATIONS if command in d["keyword_commands"]}
    assert declared, command
    assert declared <= taken, f"{command}: not taken: {sorted(declared - taken)}"


@pytest.mark.parametrize("call", sorted({c for calls in CALLS.values() for c in calls}, key=lambda c: c.__name__))
def test_no_call_takes_an_undeclared_option(call):
    commands = [command for command, calls in CALLS.items() if call in calls]
    declared = {d["keyword"] for d in DECLARATIONS if set(commands) & set(d["keyword_commands"])}
    # stvd.propagate serves stvd path too: its keywords are declared for
    # distance or path; stvd.cohort.run's threads are its own (per task).
    undeclared = set(parameters(call)) - declared - NOT_OPTIONS
    assert not undeclared, f"{call.__module__}.{call.__name__}: {sorted(undeclared)}"


@pytest.mark.parametrize("command", sorted(CALLS))
def test_a_keyword_left_out_takes_the_declared_default(command):
    for declaration in DECLARATIONS:
        if command not in declaration["keyword_commands"]:
            continue
        for call in CALLS[command]:
            parameter = parameters(call).get(declaration["keyword"])
            if parameter is None or parameter.default is inspect.Parameter.empty:
                continue
            if declaration["type"] == "switch":
                expected = declaration["keyword_is_negation"]
                # None: the library decides (refine=None is refine=True).
                assert parameter.default in (expected, None), (call.__name__, declaration["keyword"])
            else:
                assert parameter.default in (None, declaration["defaults"].get(command)), (
                    call.__name__, declaration["keyword"], parameter.default)


def test_the_package_defaults_are_the_declared_ones():
    for declaration in DECLARATIONS:
        keyword, default = declaration["keyword"], declaration["defaults"].get("distance")
        if keyword is None or declaration["type"] == "switch" or keyword == "max_anisotropy":
            continue
        if default is not None:
            assert getattr(stvd.defaults, keyword) == default, keyword
    k = next(d for d in DECLARATIONS if d["flag"] == "--k")
    assert (stvd.defaults.k, stvd.defaults.surface_k, stvd.defaults.tet_mesh_k) == (
        k["defaults"]["distance"], k["defaults"]["surface"], k["defaults"]["tet-mesh"])
    assert stvd.defaults.max_k == k["maximum"]
    cap = next(d for d in DECLARATIONS if d["flag"] == "--max-anisotropy")
    assert stvd.defaults.diffusion_max_anisotropy == cap["defaults"]["distance"]
    assert stvd.defaults.memory_check is True and stvd.defaults.refine is True


def out_of_range(declaration):
    """A value just outside the declared range."""
    if declaration["minimum"] is not None:
        value = declaration["minimum"] - (1 if declaration["type"] == "integer" else 0.5)
    else:
        value = declaration["maximum"] + 1
    return int(value) if declaration["type"] == "integer" else value


@pytest.mark.parametrize("flag", ["--k", "--steiner", "--max-distance", "--max-anisotropy", "--fa-threshold"])
def test_ranges_are_the_declared_ones_and_their_messages_speak_in_keywords(dipy_image, flag):
    declaration = next(d for d in DECLARATIONS if d["flag"] == flag)
    extra = {"method": "lanthier"} if flag == "--steiner" else {}
    with pytest.raises(ValueError) as raised:
        stvd.propagate(dipy_image, CC_BODY, **{declaration["keyword"]: out_of_range(declaration)}, **extra)
    message = str(raised.value)
    assert message.startswith(declaration["keyword"] + " must be "), message
    assert "--" not in message


@pytest.mark.parametrize("flag", ["--method", "--chain-measure", "--stencil", "--tensor-kind", "--diffusion-metric",
                                  "--tensor-frame"])
def test_choices_are_the_declared_ones(flag):
    declaration = next(d for d in DECLARATIONS if d["flag"] == flag)
    with pytest.raises(ValueError) as raised:
        stvd.propagate(str(DIPY_5D), CC_BODY, **{declaration["keyword"]: "nonsense"})
    assert str(raised.value) == (f"{declaration['keyword']}: 'nonsense' is not one of "
                                 + ", ".join(declaration["keyword_choices"]))


def test_the_surface_metric_takes_its_names_without_the_files():
    metric = next(d for d in DECLARATIONS if d["flag"] == "--metric")
    assert "field:FILE" in metric["choices"] and "field" in metric["keyword_choices"]
    vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    with pytest.raises(ValueError) as raised:
        stvd.surface_distance(vertices, [[0, 1, 2]], [0], metric="field:x")
    assert str(raised.value) == "metric: 'field:x' is not one of " + ", ".join(metric["keyword_choices"])
    with pytest.raises(ValueError, match=r"^metric='curvature' needs anisotropy=G$"):
        stvd.surface_distance(vertices, [[0, 1, 2]], [0], metric="curvature")
    assert math.isfinite(stvd.surface_distance(vertices, [[0, 1, 2]], [0], metric="curvature", anisotropy=2)[1])


def test_the_cohort_command_line_is_the_declared_options():
    parser = stvd.cohort._parser()
    flags = {a.option_strings[0]: a for a in parser._actions if a.option_strings}
    for declaration in DECLARATIONS:
        if "cohort" not in declaration["commands"]:
            continue
        action = flags[declaration["flag"]]
        assert action.dest == declaration["keyword"]
        default = declaration["defaults"]["cohort"]
        if default is not None and declaration["type"] != "choice":
            assert f"(default {default:g}" in action.help, (declaration["flag"], action.help)
        elif default is not None:
            assert f"{default} (default" in action.help, (declaration["flag"], action.help)
