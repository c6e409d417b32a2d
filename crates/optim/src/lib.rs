//! Nelder-Mead and the via-point growth loop of the planner (filled by the optim issue).
