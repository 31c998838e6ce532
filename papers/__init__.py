"""What is drawn or written for people: figures, tables, animations, citations.

``output`` (CSV with a header of parameters, figures as PNG and PDF), ``plotting`` (critical-line diagrams),
``atlas_plots``, ``animation``, ``averaging_check`` (the slow map beside the direct ODE), ``citation`` (BibTeX),
``verification`` (each formula against an independent reference: ``rocknroller verify``); ``lynch_bustamante``
reproduces the seed paper, one module per figure or table, with its errata.  Imports the analysis and the numerics, never the front door.
"""
