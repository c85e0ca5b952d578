//! Sparse assembly: pattern and scatter map built once, values filled per iteration.
