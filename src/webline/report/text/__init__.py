"""Words and tables of a report: how values are displayed, the line's description, the verdict,
the zone and winder tables, HTML pieces."""
