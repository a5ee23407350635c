//! Graphics-versus-compute throughput scenario.
