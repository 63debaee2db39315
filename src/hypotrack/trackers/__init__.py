"""hypotrack.trackers"""
