"""What a branched run's verdict finds (docs/branching.md): a web break, the stop and the
hold (``break_verdict``), the webs' and lanes' tensions, slack, strength and yield
(``web_findings``), and the winder states of the line file's ``[checks]``
(``winder_states``)."""
