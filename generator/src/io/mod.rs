//! Output: tables and VTK.
