"""The base of the package: errors, convergence status, files, progress bars,
plots, parallel runs, model registries, materials and Hertz's theory.  Nothing
here knows a model or a case (rank 0 of ``docs/architecture.md``)."""

#: the modules are imported by name (railcontact.cases.solve, ...); nothing re-exported here
__all__: list = []
