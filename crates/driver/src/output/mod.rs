//! Output files: VTK XML meshes with fields, SVG plots, written atomically.
