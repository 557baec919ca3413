"""Comparison runs (`symsynth bench`): an experiment file names a matrix of
scenes, costmap methods, planners, solvers and game parameters; each run
goes to a child process with time and memory limits, and its row is
appended to a CSV as it ends, from which a table and plots are made.

experiment  the file: schema, checks, the runs it expands to
worker      one run in a child process: the row of measurements
runner      the runs on an executor, rows appended, resumed, progress
results     the CSV's columns, reading and writing rows, the table
plots       the figures (matplotlib)
"""
