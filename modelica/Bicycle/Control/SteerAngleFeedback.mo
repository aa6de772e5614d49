within Bicycle.Control;
block SteerAngleFeedback "Steer-angle feedback for steer-angle-input models, delta = -k2*phi, eq (5)"
  parameter Real k2(unit = "1") = 1 "Gain from roll angle to steer angle";
  input Bicycle.Units.Angle phi "Roll angle";
  output Bicycle.Units.Angle delta "Steer angle";
equation
  delta = -k2*phi;
  annotation(__Cosim(export = true));
end SteerAngleFeedback;
