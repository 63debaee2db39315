"""hypotrack.scenarios"""
