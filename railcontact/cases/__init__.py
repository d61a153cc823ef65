"""Contact cases above the pipeline's layers: case files and their typed setups,
bodies and patches, the vertical balance, one case solved (:func:`solve`), many
(:func:`sweep`), cases on rail surfaces and crossings, model comparison and the
coupling of dissimilar materials (rank 5 of ``docs/architecture.md``)."""

#: the modules are imported by name (railcontact.cases.solve, ...); nothing re-exported here
__all__: list = []
