"""hypotrack.association"""
