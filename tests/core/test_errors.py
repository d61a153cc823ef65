"""railcontact.core.errors: one exception hierarchy, caught by the CLI as a one-line error."""

import inspect

import pytest

import railcontact.core.errors as errors
from railcontact.cli import main
from railcontact.core.errors import (CaseFileError, InputError, ProfileError, RailContactError,
                                UnknownModelError)
from railcontact.core.materials import Material
from railcontact.normal.base import get_normal_model


def test_every_exception_derives_from_the_base():
    classes = [c for _, c in inspect.getmembers(errors, inspect.isclass)
               if issubclass(c, BaseException) and c.__module__ == errors.__name__]
    assert len(classes) == 8
    assert all(issubclass(c, RailContactError) for c in classes)
    # bad input is also a ValueError, an unknown name also a KeyError (for callers
    # that catch the built-in types)
    for c in (ProfileError, CaseFileError, UnknownModelError, errors.ResourceError):
        assert issubclass(c, InputError) and issubclass(c, ValueError)
    assert issubclass(UnknownModelError, KeyError)


def test_unknown_model_message_is_not_quoted():
    with pytest.raises(UnknownModelError) as info:
        get_normal_model("hurtz")
    text = str(info.value)
    assert text.startswith("unknown normal model 'hurtz'") and "hertz" in text


def test_input_error_of_the_library_raised_with_its_input_named():
    with pytest.raises(InputError, match="material.poisson_ratio = 0.6"):
        Material(poisson_ratio=0.6)


def test_cli_exit_code_2_on_an_input_error(tmp_path, capsys):
    case = tmp_path / "bad.toml"
    case.write_text("[bodies]\nradii={wheel_rolling=0.46, rail_lateral=0.3}\n"
                    "normal_force=1e4\n[material]\npoisson_ratio=0.6\n")
    assert main(["solve", str(case)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("railcontact: error:") and "poisson_ratio" in err
    assert len(err.strip().splitlines()) == 1
