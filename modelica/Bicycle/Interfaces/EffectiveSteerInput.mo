within Bicycle.Interfaces;
connector EffectiveSteerInput "Effective steer angle delta_f = delta*sin(lambda) of eq (8), as a signal (input)"
  input Bicycle.Units.Angle delta_f "Effective steer angle: angle between the lines of intersection of the rear and front planes with the ground, positive to the left";
end EffectiveSteerInput;
