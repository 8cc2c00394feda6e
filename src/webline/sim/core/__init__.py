"""A line compiled into a plan (its tables and operating point) and the compiled loop that runs
it (``kernel``)."""
