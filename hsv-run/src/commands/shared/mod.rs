//! What more than one command writes or runs, apart from the shared arguments in
//! [`super`]: the cluster shards' arguments and Slurm scripts ([`shard`]), and the outputs a
//! command and `hsv-run merge` of its shards both write ([`trade_table`], [`flutter_map`],
//! [`linear_grid`]). Not a command: it imports none.

pub mod flutter_map;
pub mod linear_grid;
pub mod shard;
pub mod trade_table;
