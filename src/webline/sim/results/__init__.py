"""What a run leaves: the ``Result``, its metrics, events and findings (the verdict) and its
files."""
