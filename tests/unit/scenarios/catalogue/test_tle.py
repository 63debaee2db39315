"""A TLE file that is empty, not ASCII or not gzip is refused with the file's name."""

import gzip

import pytest

from hypotrack.scenarios.catalogue.tle import read_tle

ISS = """ISS (ZARYA)
1 25544U 98067A   19343.69339541  .00001764  00000-0  38792-4 0  9991
2 25544  51.6439 211.2001 0007417  17.6667  85.6398 15.50103472202482
"""


@pytest.mark.parametrize("content", [b"", b"\n\n   \n"])
def test_an_empty_file_is_refused_not_a_zero_row_catalogue(tmp_path, content):
    path = tmp_path / "empty.tle"
    path.write_bytes(content)
    with pytest.raises(ValueError, match=r"empty\.tle: the file holds no element set"):
        read_tle(path)


def test_a_non_ascii_file_names_the_file_and_the_byte(tmp_path):
    path = tmp_path / "accents.tle"
    path.write_bytes(ISS.replace("ISS (ZARYA)", "ISS (ZARYÁ)").encode("utf-8"))
    with pytest.raises(ValueError, match=r"accents\.tle: not an ASCII element-set file: byte 0xc3 .*\(line 1\)"):
        read_tle(path)


def test_a_gz_file_that_is_not_gzip_names_the_file(tmp_path):
    path = tmp_path / "plain.tle.gz"
    path.write_text(ISS)
    with pytest.raises(ValueError, match=r"plain\.tle\.gz: not a valid gzip file"):
        read_tle(path)
    path.write_bytes(gzip.compress(ISS.encode())[:-12])  # truncated stream
    with pytest.raises(ValueError, match=r"plain\.tle\.gz: not a valid gzip file"):
        read_tle(path)


def test_a_valid_file_still_reads(tmp_path):
    path = tmp_path / "iss.tle.gz"
    path.write_bytes(gzip.compress(ISS.encode()))
    cat = read_tle(path)
    assert len(cat) == 1 and cat["norad"].iloc[0] == 25544 and cat["group"].iloc[0] == "iss"
