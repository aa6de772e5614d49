within Bicycle.Components;
model FrontWheelGyroscope "Gyroscopic torque of the spinning front wheel on the steer axis, proportional to the roll rate"
  parameter Bicycle.Units.AngularMomentum H_g = 0 "Gyroscopic coefficient: steer torque per unit roll rate (proportional to the spin angular momentum of the front wheel)";
  Bicycle.Interfaces.Steer steer "Steer axis";
  Bicycle.Interfaces.RollRateInput rollRate "Roll rate of the rear frame";
equation
  // A roll rate der(phi) makes the spinning wheel precess: gyroscopic torque -H_g*der(phi) about
  // the steer axis, which the handlebar torque has to balance.
  steer.tau = H_g*rollRate.omega;
end FrontWheelGyroscope;
