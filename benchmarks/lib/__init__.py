"""Code the benchmark scripts and the experiments share (benchmarks/README.md): the SyRIP folds, the synthetic
clip generator and its settings, and resumable runs. Scripts import it as `benchmarks.lib` with the repository
root on sys.path."""
