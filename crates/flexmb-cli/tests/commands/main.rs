//! The command tests: the `flexmb` program run as a new user runs it, one test binary (one link) for all.

mod program;

mod applications;
mod bdf_stability_limits;
mod bench_command;
mod body_shapes;
mod cli;
mod concurrent_reduction;
mod equilibrium;
mod fe_model_file;
mod flexible_dynamics;
mod flexible_model_file;
mod geometric_stiffening;
mod high_mode_damping;
mod interrupted_run;
mod jacobian_age;
mod linear_analysis;
mod model_file;
mod model_size;
mod modes_command;
mod outputs;
mod parallel_study;
mod parameter_option;
mod physics_watchdog;
mod plot_and_spectrum;
mod published_benchmarks;
mod redundancy;
mod restart;
mod rotating_stiff_spring;
mod singular_passage;
mod singular_positions;
mod solid_bodies;
mod step_options;
mod study_file;
mod untrusted_input;
mod vtk_output;
