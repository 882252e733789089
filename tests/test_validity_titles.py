"""The validity map's plots say in their titles what the runs were: two maps of one
source (another length, step or damping gains) could not be told apart by their
title, "model: source"."""

from __future__ import annotations


def test_validity_plot_titles_say_what_the_runs_were(monkeypatch, tmp_path, capsys):
    """Two maps of one source (4 h at 2 s with damping gains, 6 h at 10 s without) had
    the same title, "model: source"."""
    from ins_errors.analysis import validity_plot
    from ins_errors.cli import main

    titles = []

    def capture(results, path, title=""):
        titles.append(title)
        return path

    monkeypatch.setattr(validity_plot, "plot_validity", capture)
    common = ["validity", "strapdown_ned", "--source", "accel_bias_x", "--motion", "static",
              "--plot", "--engine", "serial", "--no-progress"]
    assert main([*common, "--hours", "4", "--step", "2s", "-p", "k_h1=0.0293/s", "-p",
                 "k_h2=4.42e-4/s^2", "--out", str(tmp_path / "a")]) == 0
    assert main([*common, "--hours", "1.5", "--step", "10s", "--out",
                 str(tmp_path / "b")]) == 0
    capsys.readouterr()
    damped, plain = titles
    assert damped == ("strapdown_ned: accel_bias_x\n4 h runs, τ = 2 s, RK4; static; "
                      "k_h1 = 0.0293 1/s, k_h2 = 0.000442 1/s^2")
    assert plain == ("strapdown_ned: accel_bias_x\n1 h 30 min runs, τ = 10 s, RK4; static; "
                     "model defaults")
