// Particle snapshots of the shear stage for ParaView and OVITO (output.snapshot_strain): the deck
// asks LIGGGHTS for two files per snapshot with the same per-sphere columns (id, type, radius,
// position, the velocity about the streaming profile, angular velocity, force): `dump
// custom/vtk` snapshot_<step>.vtu (VTK XML unstructured grid, one vertex cell per sphere) for
// ParaView, and `dump custom` snapshot_<step>.dump (LAMMPS text dump, triclinic box) for OVITO,
// which reads LAMMPS dumps natively but has no reader for .vtu grids. After the run granflow
// indexes them in snapshots.pvd (ParaView's time series of the .vtu: time = shear strain) and
// snapshots.csv (step, time, strain, .vtu file, .dump file).
#pragma once

#include <filesystem>
#include <string>

namespace granflow::dem {

// The deck lines that write a snapshot at the shear start (timestep `shear_start_step`) and every
// `every` steps after it to snapshot_<step>.vtu and snapshot_<step>.dump in the run directory (the
// deck's own variables only: it reruns by hand as written); the fluctuating velocity is
// u − γ̇ (y − ylo) along x (the streaming profile of Lees-Edwards shear), the other components as
// they are. Empty when `every` <= 0.
std::string snapshot_commands(long every, long shear_start_step, double shear_rate);

// Indexes the snapshot_<step>.vtu files of `dir` (LIGGGHTS' bounding-box files left out) in
// dir/snapshots.pvd and, with the snapshot_<step>.dump of the same step (empty when absent), in
// dir/snapshots.csv, strain = γ̇ dt (step − shear_start_step). Returns the
// number of snapshots; throws std::runtime_error naming the file when one cannot be written.
int index_snapshots(const std::filesystem::path& dir, long shear_start_step, double dt,
                    double shear_rate);

}  // namespace granflow::dem
