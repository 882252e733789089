"""Speed benchmarks run by ``make bench`` (``python -m benchmarks``): printed, never asserted."""
