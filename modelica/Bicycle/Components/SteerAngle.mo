within Bicycle.Components;
model SteerAngle "Steer angle imposed by the rider on a vertical steer axis (lambda = 90 deg): the control variable of model (1)"
  input Bicycle.Units.Angle delta "Steer angle, positive steering to the left";
  Bicycle.Interfaces.EffectiveSteerOutput front "Effective steer angle (equal to the steer angle for a vertical steer axis)";
equation
  front.delta_f = delta;
end SteerAngle;
