//! Plots of a sweep (`sweep.csv`) as SVG files.
