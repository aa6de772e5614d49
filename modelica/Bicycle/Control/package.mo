within Bicycle;
package Control "Rider and autopilot controllers (twins of the Python controllers of cosim)"
end Control;
