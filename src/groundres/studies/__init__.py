"""Design studies: stability measures of a case over a grid of its keys, and of its failures.

One full speed sweep per grid point (:mod:`groundres.studies.grid` says which keys vary,
:mod:`groundres.studies.run` computes, here or on a Dask cluster, and
:mod:`groundres.studies.store` keeps the results chunk by chunk so that an interrupted
study resumes where it stopped); :mod:`groundres.studies.study` is the entry point."""
