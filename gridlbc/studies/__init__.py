"""Studies built on the core library: the demo, the verification report, convergence and
temperature studies, the gymnast swing-up and the figure gallery. They import the core, never
the other way round; the named problems they share live in :mod:`gridlbc.studies.problems`."""
