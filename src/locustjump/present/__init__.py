"""The presentation layer: evaluations of a run's best genome, figures,
``results.md``, the HTML report, videos and the viewer, runs compared as
samples. Reads run directories; trains nothing."""
