"""Issue #14, nothing lost, nothing silent: NaN never passes through, odd CSV files are read
or refused with the real cause named."""

import numpy as np
import pytest

from liquidamp.analysis.measured.record_model import nrmse
from liquidamp.analysis.measured.records import read_record
from liquidamp.analysis.response.harmonics import first_harmonic
from liquidamp.errors import DataFileError, ParameterError
from liquidamp.structure.testmachine import savgol_derivatives


def _sine(n=600, f=3.0, fs=200.0, Y=0.003):
    t = np.arange(n) / fs
    return t, Y * np.sin(2 * np.pi * f * t), 400 * np.cos(2 * np.pi * f * t)


# ---------------------------------------------------------------------------
# NaN in the array API


def test_first_harmonic_names_the_nan_argument_index_and_count():
    t = np.arange(64) / 64.0
    s = np.sin(2 * np.pi * t)
    s[[5, 9, 40]] = np.nan
    with pytest.raises(ParameterError, match=r"first_harmonic: signal holds 3 non-finite "
                       r"sample\(s\) of 64, the first at index 5 \(nan\)"):
        first_harmonic(t, s, 1.0)
    tt = t.copy()
    tt[2] = np.inf
    with pytest.raises(ParameterError, match=r"t holds 1 non-finite .* index 2 \(inf\).*\[s\]"):
        first_harmonic(tt, np.sin(2 * np.pi * t), 1.0)
    with pytest.raises(ParameterError, match=r"frequency must be finite \[Hz\], got nan"):
        first_harmonic(t, np.sin(2 * np.pi * t), float("nan"))
    # a clean call is unchanged
    assert first_harmonic(t, np.sin(2 * np.pi * t), 1.0) == pytest.approx(1.0 + 0j)


def test_savgol_derivatives_refuses_nan():
    t, y, _ = _sine()
    y[100] = np.nan
    y[101] = np.nan
    with pytest.raises(ParameterError, match=r"savgol_derivatives: y holds 2 non-finite "
                       r"sample\(s\) of 600, the first at index 100"):
        savgol_derivatives(t, y)
    t2 = t.copy()
    t2[7] = np.nan
    with pytest.raises(ParameterError, match=r"t holds 1 .* index 7"):
        savgol_derivatives(t2, np.sin(t))


def test_nrmse_refuses_nan_in_either_argument():
    d = np.array([1.0, -1.0, 2.0, -2.0])
    m = d.copy()
    m[2] = np.nan
    with pytest.raises(ParameterError, match=r"nrmse: model_force holds 1 non-finite sample"
                       r"\(s\) of 4, the first at index 2"):
        nrmse(m, d)
    with pytest.raises(ParameterError, match="measured_force holds 1 .* index 2"):
        nrmse(d, m)
    # pooled sequences: the index is that of the pooled samples
    with pytest.raises(ParameterError, match="model_force holds 1 .* index 5"):
        nrmse([d, np.array([0.0, np.nan])], [d, np.array([1.0, 2.0])])
    assert nrmse(d, d) == 0.0


# ---------------------------------------------------------------------------
# CSV files as spreadsheets write them


def _rows(t, y_mm, F, fmt="{:.6f}"):
    return [[fmt.format(v) for v in r] for r in zip(t, y_mm, F, strict=True)]


def test_utf8_bom_is_accepted_silently(tmp_path):
    t, y, F = _sine()
    text = "time [s],displacement [mm],force [N]\n" + "\n".join(
        ",".join(r) for r in _rows(t, y * 1e3, F)) + "\n"
    plain = tmp_path / "plain.csv"
    plain.write_text(text, encoding="utf-8")
    bom = tmp_path / "bom.csv"
    bom.write_text(text, encoding="utf-8-sig")
    assert bom.read_bytes()[:3] == b"\xef\xbb\xbf"
    a, b = read_record(plain), read_record(bom)
    assert np.array_equal(a.force, b.force) and np.array_equal(a.displacement, b.displacement)
    assert b.amplitude == pytest.approx(0.003, rel=1e-4)


@pytest.mark.parametrize("delim", [";", "\t"])
def test_semicolon_or_tab_with_decimal_comma_is_read_correctly(tmp_path, delim):
    t, y, F = _sine()
    rows = [delim.join(c.replace(".", ",") for c in r) for r in _rows(t, y * 1e3, F)]
    p = tmp_path / "eu.csv"
    p.write_text(delim.join(["time [s]", "displacement [mm]", "force [N]"]) + "\n"
                 + "\n".join(rows) + "\n", encoding="utf-8-sig")
    r = read_record(p)
    assert r.frequency == pytest.approx(3.0, rel=1e-6)
    assert r.amplitude == pytest.approx(0.003, rel=1e-4)
    assert r.force.max() == pytest.approx(400.0, rel=1e-3)
    assert r.time.size == t.size - 20  # nothing lost but the filter's edges


def test_decimal_comma_in_a_comma_separated_file_is_named(tmp_path):
    t, y, F = _sine()
    rows = [",".join(c.replace(".", ",") for c in r) for r in _rows(t, y * 1e3, F)]
    p = tmp_path / "mixed.csv"
    p.write_text("time [s],displacement [mm],force [N]\n" + "\n".join(rows) + "\n")
    with pytest.raises(DataFileError, match=r"mixed.csv, line 2: 6 fields separated by ',', "
                       r"the header has 3; the values seem to use a decimal comma"):
        read_record(p)


def test_thousands_separator_is_named(tmp_path):
    t, y, F = _sine()
    rows = [";".join(c.replace(".", ",") for c in r) for r in _rows(t, y * 1e3, F)]
    rows[3] = "0,015;0,1;1.234,5"
    p = tmp_path / "thousands.csv"
    p.write_text("time [s];displacement [mm];force [N]\n" + "\n".join(rows) + "\n")
    with pytest.raises(DataFileError, match=r"line 5, column 3 \(force\): '1.234,5' is not a "
                       r"number \(it holds both '.' and ','"):
        read_record(p)


def test_binary_file_is_refused_naming_the_file(tmp_path):
    p = tmp_path / "record.xlsx"
    p.write_bytes(b"PK\x03\x04\x14\x00\x06\x00" + bytes(range(256)) * 4)
    with pytest.raises(DataFileError, match=r"record.xlsx is not a text CSV file \(binary "
                       r"content: NUL byte at offset 5"):
        read_record(p)
    q = tmp_path / "noise.bin"
    q.write_bytes(bytes(np.random.default_rng(0).integers(1, 32, 2000, dtype=np.uint8)))
    with pytest.raises(DataFileError, match="noise.bin is not a text CSV file"):
        read_record(q)


def test_utf16_excel_export_is_read(tmp_path):
    t, y, F = _sine()
    p = tmp_path / "u16.csv"
    p.write_text("time [s]\tdisplacement [mm]\tforce [N]\n" + "\n".join(
        "\t".join(r) for r in _rows(t, y * 1e3, F)) + "\n", encoding="utf-16")
    assert read_record(p).amplitude == pytest.approx(0.003, rel=1e-4)
