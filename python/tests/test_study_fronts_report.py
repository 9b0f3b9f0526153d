"""study(), fronts(), report() and open() on study.h5 and fronts.h5."""
import h5py
import numpy as np
import pytest

import slipfront
from conftest import SOURCE


def mini_study(tmp_path, **changes):
    """A friction-law study of 4 runs (2 N x 2 seeds, 5 rates, 400 steps each: ~0.05 s)."""
    text = f'''study = "mini"
kind = "friction_law"
scene = "{SOURCE / 'configs' / 'friction_law.toml'}"
set = ['models=["continuum","discrete"]', "drive.points=5", "time.steps=400"]
seeds = 2
[vary]
"discrete.contacts_per_site" = [100, 1000]
'''
    path = tmp_path / "mini.toml"
    path.write_text(text)
    return path


def test_study_tables_scalars_and_runs(tmp_path):
    ticks = []
    st = slipfront.study(mini_study(tmp_path), out=tmp_path / "s", threads=2, progress=ticks.append)
    assert isinstance(st, slipfront.Study) and st.status == "complete"
    assert st.name == "mini" and st.study_kind == "friction_law"
    assert ticks[-1]["runs_done"] == ticks[-1]["runs"] == 4
    table = st.tables["friction_law_error"]
    assert list(table["N"]) == [100.0, 1000.0]
    assert table.descriptions["N"]  # each column's description from the file
    with h5py.File(st.path) as f:
        assert np.array_equal(table["total"], f["study/tables/friction_law_error/total"][()], equal_nan=True)
    rec = table.to_records()
    assert rec.dtype.names == tuple(k for k in table if np.ndim(table[k]) == 1) and len(rec) == 2
    assert len(st.runs) == 4 and all(p.is_file() for p in st.run_files())
    run0 = slipfront.open(st.run_files()[0])
    assert run0.models == ["continuum", "discrete"] and "sigma" in run0["discrete"].friction_law
    # a study is resumed: the same call again skips every run
    again = slipfront.study(mini_study(tmp_path), out=tmp_path / "s", progress=False)
    assert "0 run now, 4 skipped" in again.completed.stdout


def test_study_table_as_pandas(tmp_path):
    pd = pytest.importorskip("pandas")
    st = slipfront.study(mini_study(tmp_path), out=tmp_path / "s", progress=False)
    df = st.tables["friction_law_error"].to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df["N"]) == [100.0, 1000.0]
    assert df.attrs["descriptions"]["N"] == st.tables["friction_law_error"].descriptions["N"]


def test_study_errors_name_the_key(tmp_path):
    with pytest.raises(slipfront.ConfigError) as e:
        slipfront.study(mini_study(tmp_path), out=tmp_path / "s", overrides={"interface.kappa": -2.0}, progress=False)
    assert "interface.kappa" in e.value.message and "got -2" in e.value.message


def test_fronts(tmp_path):
    fr = slipfront.fronts(SOURCE / "configs" / "steady_front.toml", out=tmp_path / "f")
    assert isinstance(fr, slipfront.Fronts) and fr.status == "complete"
    # docs/fronts.md: the branch ends at sigma_c^d, where c_min is reached
    assert 5 < fr.c_min < 30 and fr.branch_attrs["end"] == "saddle_node"
    assert len(fr.branch["c"]) == len(fr.branch["sigma_d"]) > 3
    p = fr.profiles[0]
    assert p["xi"].shape == p["A"].shape and p["c"] > 0
    with pytest.raises(slipfront.ConfigError, match="homogeneous"):
        slipfront.fronts(SOURCE / "configs" / "fig1.toml", out=tmp_path / "g")


def test_report(tiny, tmp_path):
    slipfront.run(tiny, out=tmp_path / "r" / "tiny", progress=False)
    md = slipfront.report(tmp_path / "r")
    assert md.is_file() and "tiny" in md.read_text()
    assert any((tmp_path / "r" / "figures").rglob("*.png"))
    with pytest.raises(slipfront.RunError):
        slipfront.report(tmp_path / "nothing")
