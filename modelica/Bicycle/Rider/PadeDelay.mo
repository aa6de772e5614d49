within Bicycle.Rider;
block PadeDelay "Neuromuscular delay exp(-s*tau) of the rider as a Pade approximation of order n"
  parameter Bicycle.Units.Time tau(min = 1e-6) = 0.1 "Delay (0.1 s for steer torque, 0.3 s for upper-body lean)";
  parameter Integer n(min = 1, max = 10) = 2 "Order of the approximation (numerator and denominator degree); structural";
  input Real u "Signal into the delay";
  output Real y "Delayed signal";
protected
  Real d[n + 1] "Denominator coefficient of s^(k-1), d[1] = 1";
  Real a[n + 1] "Denominator coefficients normalized by the leading one";
  Real b[n + 1] "Numerator coefficients normalized by the leading denominator coefficient";
  Real x[n](each start = 0, each fixed = true) "States of the controllable canonical form";
  Real feedback[n] "Running sums of a[k]*x[k]";
  Real output_[n] "Running sums of (b[k] - a[k]*b[n+1])*x[k]";
equation
  // Pade coefficients: d[k+1] = d[k]*tau*(n-k+1)/(k*(2n-k+1)); the numerator alternates in sign.
  d[1] = 1;
  for k in 1:n loop
    d[k + 1] = d[k]*tau*(n - k + 1)/(k*(2*n - k + 1));
  end for;
  for k in 1:n + 1 loop
    a[k] = d[k]/d[n + 1];
    b[k] = (-1)^(k - 1)*d[k]/d[n + 1];
  end for;
  for i in 1:n - 1 loop
    der(x[i]) = x[i + 1];
  end for;
  // Dot products as running sums (pymoca treats a[1:n]*x as a matrix product).
  feedback[1] = a[1]*x[1];
  output_[1] = (b[1] - a[1]*b[n + 1])*x[1];
  for k in 2:n loop
    feedback[k] = feedback[k - 1] + a[k]*x[k];
    output_[k] = output_[k - 1] + (b[k] - a[k]*b[n + 1])*x[k];
  end for;
  der(x[n]) = u - feedback[n];
  y = output_[n] + b[n + 1]*u;
  annotation(__Cosim(export = true), Documentation(info = "<html>
<p>Transfer function N(s)/D(s) with D(s) = sum d[k+1] s^k and N(s) = sum (-1)^k d[k+1] s^k, the
[n/n] Pade approximant of exp(-s tau) (identical to python-control's <code>pade(tau, n)</code>).
The order n fixes the number of states and is therefore fixed when the FMU is built.</p>
</html>"));
end PadeDelay;
