"""Judging the roots: stability over the sweep, scans over speed, the lag damping a design
needs (Deutsch criterion and the exact search), and what the model can resolve."""
