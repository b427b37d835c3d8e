"""Run records (MCAP): an adapter kept apart from the pure core."""
