"""The calibench report: reads `calibench run` directories (runs.csv, summary.csv, schema.json and
the tracking files) and writes report.md, its appendix pages and figures.

Modules:
  io        reading run directories, writing files, paths relative to the report
  schema    schema.json: the quantities (calibench's metric table) and each sweep's role
  stats     paired comparisons (Lilliefors, t / Wilcoxon, bootstrap, Holm) and coverage
  scores    sweep points and their scores (summary.csv's statistics, the comparisons)
  tables    Markdown tables and number formats
  plots     the method palette and shared panels (matplotlib, Agg)
  sections  one module per section; answers.py writes the first page
  document  the pages; cli the command line (python3 -m calibench_report)
"""
