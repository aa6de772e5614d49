within Bicycle.Interfaces;
connector LeanInput "Lean of a body that moves relative to the rear frame, weighted with its inertia (input)"
  input Bicycle.Units.AngularMomentumIntegral H "J_r*theta: moment of inertia about the x axis times lean angle relative to the frame; der(H) is the body's angular momentum relative to the frame";
end LeanInput;
