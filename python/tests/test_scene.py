"""Scene, check() and the program's errors as ConfigError(file, key, reason)."""
import pytest

import slipfront
from conftest import SOURCE, tiny_config


def test_from_toml_and_set_check_resolve_every_key(tiny_file):
    scene = slipfront.Scene.from_toml(tiny_file).set("bulk.length", 50.0).set("time.t_end", 30)
    check = scene.check()
    # the program's resolved configuration: the overrides applied, the defaults filled in
    assert check.config["bulk"]["length"] == 50.0
    assert check.config["time"]["t_end"] == 30.0
    assert check.config["measure"]["A_tip"] == 0.5          # a default the file does not give
    assert any("steps" in line for line in check.estimate)    # the estimate's lines
    assert scene.to_dict()["bulk"]["length"] == 50.0


def test_from_dict_equals_from_toml(tiny_file):
    a = slipfront.Scene.from_dict(tiny_config()).check()
    b = slipfront.Scene.from_toml(tiny_file).check()
    assert a.toml == b.toml


def test_error_of_an_override_names_file_key_and_reason(tiny_file):
    scene = slipfront.Scene.from_toml(tiny_file).set("interface.alpha", 0.9)
    with pytest.raises(slipfront.ConfigError) as e:
        scene.check()
    assert e.value.file == str(tiny_file)
    assert e.value.key == "--set interface.alpha"
    assert e.value.reason.startswith("must be >= 1")


def test_error_in_a_dictionary_names_the_key(tmp_path):
    with pytest.raises(slipfront.ConfigError) as e:
        slipfront.Scene.from_dict(tiny_config(interface__kappa=-1.0)).check()
    assert (e.value.file, e.value.key) == ("<dict>", "interface.kappa")
    assert "got -1" in e.value.reason
    with pytest.raises(slipfront.ConfigError) as e:  # an unknown key: the program suggests the nearest
        slipfront.Scene.from_dict(tiny_config(interface__alpah=1.0)).check()
    assert e.value.key == "interface.alpah" and "did you mean 'alpha'" in e.value.reason


def test_run_refuses_before_any_work(tmp_path):
    scene = slipfront.Scene.from_dict(tiny_config()).set("grid.dx", "abc")
    with pytest.raises(slipfront.ConfigError) as e:
        slipfront.run(scene, out=tmp_path / "o", progress=False)
    assert e.value.key == "--set grid.dx" and "expected a number" in e.value.reason
    assert not (tmp_path / "o").exists()  # nothing created


def test_missing_file_and_values():
    with pytest.raises(slipfront.ConfigError):
        slipfront.Scene.from_toml(SOURCE / "configs" / "no_such_scene.toml")
    assert slipfront.scene.toml_value([1, 2.5, "a\"b", True]) == '[1, 2.5, "a\\"b", true]'
    assert slipfront.scene.toml_value(1e-300) == "1e-300"
    assert slipfront.scene.toml_value(3.0) == "3.0"
    with pytest.raises(TypeError):
        slipfront.scene.toml_value({"a": 1})


def test_program_not_found(tiny, monkeypatch, tmp_path):
    with pytest.raises(FileNotFoundError, match="SLIPFRONT_PROGRAM"):
        tiny.check(program=tmp_path / "nothing")
