//! Homogeneous compression of a block under a rigid platen, and 1D conduction through it (the accompanying bar problem).
