"""OptionError: one error, worded by each front end (the API as ``mode='2d'``, the shell as ``--mode 2d``)."""

from __future__ import annotations

import re

import polars as pl
import pytest

from omega_prime_visibility import OptionError, Query, get_visibility_df
from omega_prime_visibility.cli.common import flag, shell_spelling
from omega_prime_visibility.inputs.errors import UNSET, Setting, api_spelling

TWO_CARS = pl.DataFrame(
    {"total_nanos": [0, 0], "frame": [0, 0], "idx": [0, 1], "x": [0.0, 10.0], "y": [0.0, 0.0], "yaw": [0.0, 0.0]}
).with_columns(length=pl.lit(4.0), width=pl.lit(2.0), type=pl.lit(2))

BAD_QUESTIONS = [
    ({"measure": "area", "mode": "3d"}, "measure", "--measure area measures footprints in 2D; use --mode 2d"),
    ({"measure": "area", "engine": "sweep"}, "measure", "leave --engine unset, not 'sweep'"),
    ({"engine": "raycast3d"}, "engine", "for --mode 2d; available: sweep, visilibity ('raycast3d' is a 3d engine"),
    ({"engine": "sweep", "mode": "3d"}, "engine", "is a 2d engine: pass --mode 2d)"),
    ({"mode": "4d"}, "mode", "--mode must be '2d' or '3d', not '4d'"),
    ({"targets": ["lorries"]}, "targets", "--targets: unknown object kind 'lorries'"),
    ({"occluders": [1, "car"]}, "occluders", "--occluders takes either names or idx, not a mix"),
    ({"observers": "everyone"}, "ego_idx", "--ego must be an int, a list of ints or 'all'"),
]


@pytest.mark.parametrize(("options", "option", "shell"), BAD_QUESTIONS)
def test_each_front_end_words_the_error_itself(options, option, shell) -> None:
    with pytest.raises(OptionError) as caught:
        query = Query(**options)
        get_visibility_df(TWO_CARS, query=query.replace(observers=0))
    error = caught.value
    assert error.option == option
    worded = error.words(shell_spelling, flag(error.option))
    assert shell in worded, worded
    # the API's spelling of a setting (name='value') never reaches the shell, and the shell's never the API
    assert not re.search(r"\b(mode|measure|engine|map_occluders)=", worded), worded
    assert "--" not in str(error), str(error)


def test_api_words_settings_as_keywords() -> None:
    with pytest.raises(OptionError) as caught:
        Query(measure="area", mode="3d")
    assert str(caught.value) == "measure='area' measures footprints in 2D; use mode='2d' (or measure='angle' in 3D)"
    assert str(caught.value) == caught.value.detail


def test_plain_messages_keep_their_braces_and_get_the_option_in_front() -> None:
    error = OptionError.plain("targets", "no such kind {'a': 1}")
    assert str(error) == "targets: no such kind {'a': 1}"
    assert error.words(api_spelling, "--targets") == "--targets: no such kind {'a': 1}"
    named = OptionError.plain("ego_idx", "ego_idx must be one idx")
    assert named.words(api_spelling, "--ego") == "--ego must be one idx"


@pytest.mark.parametrize(
    ("setting", "api", "shell"),
    [
        (Setting("mode", "2d"), "mode='2d'", "--mode 2d"),
        (Setting("engine"), "engine", "--engine"),
        (Setting("ego_idx", 3), "ego_idx=3", "--ego 3"),
        (Setting("map_occluders", True), "map_occluders=True", "--map-occluders"),
        (Setting("map_occluders", "FILE.xodr"), "map_occluders='FILE.xodr'", "--map-occluders --map FILE.xodr"),
        (Setting("static_occluder_polys", UNSET), "static_occluder_polys", "--static"),
    ],
)
def test_spellings(setting: Setting, api: str, shell: str) -> None:
    assert api_spelling(setting) == api
    assert shell_spelling(setting) == shell
