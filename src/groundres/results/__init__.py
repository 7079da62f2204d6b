"""What an analysis hands back: result objects, mode shapes, the summary, the data set, and the
files and output folders they are written to."""
