within Bicycle.Interfaces;
connector RollRateOutput "Roll rate of the rear frame, as a signal (output)"
  output Bicycle.Units.AngularVelocity omega "Roll rate der(phi), positive when the lean to the right increases";
end RollRateOutput;
