"""grainlift's Python analysis: io (reading dem.h5, fem.h5, summary.json, calibration files),
plots (matplotlib helpers) and stats (block means, pooled errors, Richardson extrapolation).
The product's scripts (scripts/report.py, plot_results.py, plot_rheology.py) and every study
under studies/ import it; python/ or, installed, share/grainlift/ must be on sys.path: each script
puts the folder that holds grainlift/ first on sys.path."""
