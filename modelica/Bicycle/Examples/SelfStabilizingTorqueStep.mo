within Bicycle.Examples;
model SelfStabilizingTorqueStep "Self-stabilizing bicycle at 6 m/s under a constant steer torque (cf. Figure 5)"
  Bicycle.Bicycles.SelfStabilizing bicycle(V = 6, T = 1) "Bicycle with a constant 1 N.m steer torque";
  annotation(experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01));
end SelfStabilizingTorqueStep;
