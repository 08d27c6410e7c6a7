"""Input/output: atomic writers, JSON, Stribeck CSV, EPOS exports, EMPS .mat, recordings. File formats
only: nothing here imports the rest of the package (scenarios are built in :mod:`lugre_jax.scenario`).

Every loader reports a malformed file by path and line (and column where it applies); every writer
is atomic (temporary file, then rename).
"""

from ._any import read_recording as read_recording
from ._atomic import (
    MANIFEST as MANIFEST,
    atomic_folder as atomic_folder,
    atomic_path as atomic_path,
    check_folder_replaceable as check_folder_replaceable,
    csv_size_estimate as csv_size_estimate,
    deferred_signals as deferred_signals,
    replace_folder as replace_folder,
    save_figure as save_figure,
    write_csv as write_csv,
    write_json as write_json,
    write_manifest as write_manifest,
)
from ._emps import (
    EMPS_REFERENCE as EMPS_REFERENCE,
    SI_UNITS as SI_UNITS,
    EmpsRun as EmpsRun,
    default_emps_path as default_emps_path,
    load_emps as load_emps,
    read_emps_mat as read_emps_mat,
)
from ._epos import (
    TRO2021_NOMINAL_TORQUE_NM as TRO2021_NOMINAL_TORQUE_NM,
    EposRecording as EposRecording,
    load_epos_file as load_epos_file,
    load_epos_steady_state as load_epos_steady_state,
    load_friction_data as load_friction_data,
)
from ._recording import (
    PAPER_UNITS as PAPER_UNITS,
    Recording as Recording,
    derive_kinematics as derive_kinematics,
    load_recording as load_recording,
    recording_from_arrays as recording_from_arrays,
    write_recording as write_recording,
)
from ._stribeck_data import (
    StribeckData as StribeckData,
    load_stribeck_csv as load_stribeck_csv,
    summarise_samples as summarise_samples,
)
from ._validate import load_params_json as load_params_json, read_json as read_json  # noqa: E402
