"""hypotrack.hypotheses"""
