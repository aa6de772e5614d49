within Bicycle.Interfaces;
connector RollRateInput "Roll rate of the rear frame, as a signal (input)"
  input Bicycle.Units.AngularVelocity omega "Roll rate der(phi), positive when the lean to the right increases";
end RollRateInput;
