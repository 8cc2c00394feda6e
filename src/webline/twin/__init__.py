"""Digital twin of a line: measured traces in, identification experiments, fitted parameters,
controllers tuned on the (fitted) line. Sits above ``report`` (it draws with its figures) and
below the command line."""
