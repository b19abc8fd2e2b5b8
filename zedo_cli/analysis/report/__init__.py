"""The self-contained HTML report of an analysis (`report`), the clip's own sections (`clip_report`), the
features in plain words (`plain_words`), inline SVG figures (`figures`, matplotlib imported inside the
functions) and the HTML helpers the pages share (`markup`).

The highest of the analysis's layers: it renders an `Analysis`, so it may import every other part of
`analysis` and nothing of it imports the report (docs/ARCHITECTURE.md). Not imported by `analysis`'s
`__init__`, so that matplotlib loads only when a report is asked for.
"""
