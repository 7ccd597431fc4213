#!/usr/bin/python3
"""plot_ensemble.main_outputs on a wet ensemble's scalars: the displacements first, then the
reservoir's wave, run-up and water force; gauges_from_run_start (which repeats the gauges'
keys) never. Exits 1 with the list it got otherwise."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import plot_ensemble  # noqa: E402

keys = ["broken_joints", "steps", "final_energies.kinetic",
        "gauges.gauge1.max_displacement_m", "gauges.gauge1.peak_velocity_mps",
        "gauges.gauge2.max_displacement_m",
        "gauges_from_run_start.gauge1.max_displacement_m", "gauges_from_run_start.gauge2.max_displacement_m",
        "heller_hager.amplitude_m", "max_wave_amplitude_m", "max_runup_m.far_bank",
        "moving_water.force_on_curves.intake.max_force_N_per_m", "moving_water.force_on_curves.intake.time_s",
        "mean_max_displacement_m"]
ens = {"scalars": {k: {"ci95": [0.0, 1.0]} for k in keys}}
got = plot_ensemble.main_outputs(ens)
want = ["gauges.gauge1.max_displacement_m", "gauges.gauge2.max_displacement_m", "mean_max_displacement_m",
        "max_runup_m.far_bank", "max_wave_amplitude_m", "moving_water.force_on_curves.intake.max_force_N_per_m",
        "gauges.gauge1.peak_velocity_mps", "broken_joints"]
if got != want:
    print("main_outputs:", got, "\nexpected:   ", want)
    sys.exit(1)
print("OK")
